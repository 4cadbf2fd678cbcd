// Species files (scenes/species.h): the four appendix species, Arbaro XML, and file:line errors.

#include "core/error.h"
#include "geometry/trees/tree_stats.h"
#include "scenes/species.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace sylva {
namespace {

const std::filesystem::path kSpecies = std::filesystem::path(SYLVA_SOURCE_DIR) / "data" / "species";

const WeberPennParams& wp(const Species& s) { return std::get<WeberPennParams>(s.model); }

// The ParseError message for `text` read as `name`.
std::string species_error(const std::string& text, const std::string& name = "bad.toml") {
  try {
    parse_species(text, name);
  } catch (const ParseError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Species, FourAppendixSpeciesLoad) {
  const Species aspen = load_species(kSpecies / "quaking_aspen.toml");
  EXPECT_EQ(aspen.name, "Quaking Aspen");
  EXPECT_TRUE(aspen.warnings.empty());
  const WeberPennParams& a = wp(aspen);
  EXPECT_EQ(a.shape, 7);
  EXPECT_FLOAT_EQ(a.base_size, 0.4f);
  EXPECT_FLOAT_EQ(a.scale, 13.0f);
  EXPECT_FLOAT_EQ(a.ratio_power, 1.2f);
  EXPECT_EQ(a.lobes, 5);
  EXPECT_FLOAT_EQ(a.level[1].down_angle, 60.0f);
  EXPECT_FLOAT_EQ(a.level[1].down_angle_v, -50.0f);
  EXPECT_EQ(a.level[1].branches, 50);
  EXPECT_FLOAT_EQ(a.level[2].curve_v, 75.0f);
  EXPECT_FLOAT_EQ(a.level[3].rotate, 77.0f);
  EXPECT_EQ(a.leaves, 25);
  EXPECT_EQ(a.leaf_shape, LeafShape::Oval);

  const Species t_species = load_species(kSpecies / "black_tupelo.toml");
  const WeberPennParams& t = wp(t_species);
  EXPECT_EQ(t.levels, 4);
  EXPECT_FLOAT_EQ(t.level[0].taper, 1.1f);
  EXPECT_FLOAT_EQ(t.level[2].curve_v, 150.0f);
  const Species w_species = load_species(kSpecies / "weeping_willow.toml");
  const WeberPennParams& w = wp(w_species);
  EXPECT_EQ(w.base_splits, 2);
  EXPECT_FLOAT_EQ(w.level[1].rotate, -120.0f);
  EXPECT_EQ(w.level[3].branches, 300);
  EXPECT_FLOAT_EQ(w.attraction_up, -3.0f);
  EXPECT_FLOAT_EQ(w.prune_ratio, 1.0f);
  EXPECT_FLOAT_EQ(w.envelope.power_low, 0.001f);
  const Species o_species = load_species(kSpecies / "california_black_oak.toml");
  const WeberPennParams& o = wp(o_species);
  EXPECT_FLOAT_EQ(o.scale_v, 10.0f);
  EXPECT_FLOAT_EQ(o.level[1].curve_back, -70.0f);
  EXPECT_FLOAT_EQ(o.level[2].curve_v, -30.0f);
}

TEST(Species, LevelPrefixAtTopLevelAndArbaroDefaults) {
  const Species s = parse_species("model = \"weber-penn\"\n1DownAngle = 45\n[level2]\nBranches = 7\n", "x.toml");
  EXPECT_EQ(s.name, "x");
  EXPECT_FLOAT_EQ(wp(s).level[1].down_angle, 45.0f);
  EXPECT_EQ(wp(s).level[2].branches, 7);
  // Arbaro's defaults for everything else.
  EXPECT_FLOAT_EQ(wp(s).scale, 10.0f);
  EXPECT_FLOAT_EQ(wp(s).base_size, 0.25f);
  EXPECT_FLOAT_EQ(wp(s).level[0].length, 1.0f);
  EXPECT_EQ(wp(s).level[1].branches, 10);
  EXPECT_FLOAT_EQ(wp(s).level[2].down_angle, 30.0f);
  EXPECT_EQ(wp(s).level[0].curve_res, 3);
  EXPECT_EQ(wp(s).level[2].curve_res, 1);
  EXPECT_FLOAT_EQ(wp(s).leaf_scale, 0.2f);
  EXPECT_FLOAT_EQ(wp(s).leaf_bend, 0.3f);
  EXPECT_EQ(wp(parse_species("model = \"weber-penn\"\nLeafShape = \"maple5\"\n", "x.toml")).leaf_shape,
            LeafShape::Maple5);
  EXPECT_EQ(wp(parse_species("model = \"weber-penn\"\nLeafShape = 2\n", "x.toml")).leaf_shape, LeafShape::Oak3);
}

TEST(Species, TomlErrorsCarryFileAndLine) {
  EXPECT_EQ(species_error("name = \"x\"\n"), "bad.toml:1: missing key 'model' (e.g. model = \"weber-penn\")");
  EXPECT_EQ(species_error("model = \"lsys\"\n"),
            "bad.toml:1: unknown model \"lsys\" (this version reads \"weber-penn\", \"lsystem\", \"aspen-grammar\", "
            "\"treemaker\", \"hart-baker\", \"fournier-grindal\")");
  EXPECT_EQ(species_error("model = \"weber-penn\"\nShape = 7\nBaseSise = 0.4\n"),
            "bad.toml:3: unknown parameter 'BaseSise'");
  EXPECT_EQ(species_error("model = \"weber-penn\"\n\nShape = 9\n"), "bad.toml:3: 'Shape' must be in [0, 8], not 9");
  EXPECT_EQ(species_error("model = \"weber-penn\"\nShape = 7.5\n"), "bad.toml:2: 'Shape' must be an integer, not 7.5");
  EXPECT_EQ(species_error("model = \"weber-penn\"\nScale = \"big\"\n"),
            "bad.toml:2: 'Scale' must be a number, not \"big\"");
  EXPECT_EQ(species_error("model = \"weber-penn\"\nScale = -1\n"),
            "bad.toml:2: 'Scale' must be at least 1e-06, not -1");
  EXPECT_EQ(species_error("model = \"weber-penn\"\n1DownAngle = 60\n[level1]\nDownAngle = 50\n"),
            "bad.toml:4: parameter '1DownAngle' given twice (first on line 2)");
  EXPECT_EQ(species_error("model = \"weber-penn\"\n[level1]\nDownAngel = 50\n"),
            "bad.toml:3: unknown level parameter 'DownAngel' in [level1]");
  EXPECT_EQ(species_error("model = \"weber-penn\"\n[level7]\nLength = 1\n"),
            "bad.toml:2: unknown table [level7] (expected [level0] .. [level3])");
  EXPECT_EQ(species_error("model = \"weber-penn\"\n[level1]\nCurveRes = 0\n"),
            "bad.toml:3: '1CurveRes' must be in [1, 10000], not 0");
  EXPECT_EQ(
      species_error("model = \"weber-penn\"\nLeafShape = \"fern\"\n"),
      "bad.toml:2: unknown LeafShape \"fern\" (expected 0..5 or oval, triangle, oak3, maple3, maple5, leaflets3)");
  EXPECT_EQ(species_error("model = \"weber-penn\"\nShape = [1]\n"), "bad.toml:2: 'Shape' must be a number");
  EXPECT_EQ(species_error("model = \"weber-penn\"\nShape = \n").substr(0, 11), "bad.toml:2:");  // TOML syntax
  EXPECT_EQ(species_error("x", "tree.obj"),
            "tree.obj:0: unknown species file type (expected .toml or .xml or .lsys or .grammar or .tmpl or "
            ".hbtree)");
  EXPECT_THROW(load_species(kSpecies / "does_not_exist.toml"), ParseError);
}

TEST(Species, ArbaroXml) {
  const Species x = load_species(kSpecies / "quaking_aspen_arbaro.xml");
  EXPECT_EQ(x.name, "quaking_aspen_arbaro");
  ASSERT_EQ(x.warnings.size(), 1u);  // Smooth is read and ignored
  EXPECT_NE(x.warnings[0].find("quaking_aspen_arbaro.xml:"), std::string::npos);
  EXPECT_NE(x.warnings[0].find("Smooth"), std::string::npos);
  EXPECT_FLOAT_EQ(wp(x).level[1].down_angle_v, -50.0f);
  EXPECT_FLOAT_EQ(wp(x).level[1].branch_dist, 1.0f);
  // An Arbaro file is read as Arbaro reads it; it holds the TOML species' values, so it gives the
  // TOML species' tree under `reading = "arbaro"`, bit for bit, and another under the paper's.
  EXPECT_EQ(wp(x).reading, wp::Reading::Arbaro);
  const std::filesystem::path toml = kSpecies / "quaking_aspen.toml";
  const Species t = load_species(toml);
  EXPECT_EQ(wp(t).reading, wp::Reading::Paper);
  std::ifstream in(toml);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const Species t_arbaro = parse_species("reading = \"arbaro\"\n" + text, toml);
  EXPECT_EQ(hash_tree_mesh(make_species_mesh(x, 5)), hash_tree_mesh(make_species_mesh(t_arbaro, 5)));
  EXPECT_NE(hash_tree_mesh(make_species_mesh(x, 5)), hash_tree_mesh(make_species_mesh(t, 5)));

  const Species s = parse_species(
      "<?xml version='1.0'?>\n<arbaro>\n <species name='demo'>\n  <param name='Levels' value='2'/>\n"
      "  <param name='1Branches' value='12'/>\n  <param name='LeafShape' value='disc'/>\n"
      "  <param name='LeafDistrib' value='3'/>\n  <param name='Species' value='renamed'/>\n </species>\n</arbaro>\n",
      "demo.xml");
  EXPECT_EQ(s.name, "renamed");
  EXPECT_EQ(wp(s).levels, 2);
  EXPECT_EQ(wp(s).level[1].branches, 12);
  EXPECT_EQ(wp(s).leaf_shape, LeafShape::Oval);
  EXPECT_EQ(wp(s).leaf_distrib, 3);
  EXPECT_FLOAT_EQ(wp(s).leaf_stem_len, 0.5f);  // Arbaro default
}

TEST(Species, ReadingKey) {
  const std::string head = "model = \"weber-penn\"\n";
  EXPECT_EQ(wp(parse_species(head, "a.toml")).reading, wp::Reading::Paper);
  EXPECT_EQ(wp(parse_species(head + "reading = \"arbaro\"\n", "a.toml")).reading, wp::Reading::Arbaro);
  EXPECT_EQ(wp(parse_species(head + "reading = \"paper\"\n", "a.toml")).reading, wp::Reading::Paper);
  EXPECT_EQ(species_error(head + "reading = \"sapling\"\n"),
            "bad.toml:2: 'reading' must be \"paper\" or \"arbaro\", not \"sapling\"");
  EXPECT_EQ(species_error(head + "reading = 2\n"), "bad.toml:2: 'reading' must be \"paper\" or \"arbaro\", not 2");
  // An Arbaro file may ask for the paper's reading.
  const Species x = parse_species(
      "<arbaro>\n<species name='x'>\n<param name='reading' value='paper'/>\n</species></arbaro>\n", "x.xml");
  EXPECT_EQ(wp(x).reading, wp::Reading::Paper);
}

TEST(Species, TrunkBelowTheHorizontalWarns) {
  const Species s = parse_species("model = \"weber-penn\"\n0DownAngle = 100\n", "down.toml");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("down.toml: warning: 0DownAngle"), std::string::npos) << s.warnings[0];
  EXPECT_TRUE(load_species(kSpecies / "california_black_oak.toml").warnings.empty());
}

TEST(Species, ArbaroXmlErrors) {
  const std::string head = "<arbaro>\n<species name='x'>\n";
  EXPECT_EQ(species_error(head + "<param name='Shape' value='seven'/>\n</species></arbaro>", "x.xml"),
            "x.xml:3: 'Shape' must be a number, not \"seven\"");
  EXPECT_EQ(
      species_error(head + "<param name='Shape' value='1'/>\n<param name='WoodType' value='Oak'/>\n</species></arbaro>",
                    "x.xml"),
      "x.xml:4: unknown parameter 'WoodType'");
  EXPECT_EQ(species_error(head + "<param name='Shape'/>\n</species></arbaro>", "x.xml"),
            "x.xml:3: <param name=\"Shape\"> without a value attribute");
  EXPECT_EQ(species_error(head + "\n<param name='4Length' value='1'/>\n</species></arbaro>", "x.xml"),
            "x.xml:4: '4Length': levels deeper than 3 reuse level 3's parameters");
  EXPECT_EQ(species_error("<tree/>", "x.xml"),
            "x.xml:1: not an Arbaro species file: expected an <arbaro> root element");
  EXPECT_EQ(species_error(head + "<param name='Shape' value='1'>\n</species></arbaro>", "x.xml").substr(0, 8),
            "x.xml:4:");
}

TEST(Species, OptionsReachTheGenerator) {
  const Species s = load_species(kSpecies / "quaking_aspen.toml");
  const TreeModel calm = make_species_model(s, 3);
  TreeOptions windy;
  windy.wind_speed = 4.0f;
  windy.wind_gust = 2.0f;
  windy.time_s = 10.0f;
  const TreeModel moved = make_species_model(s, 3, windy);
  EXPECT_EQ(calm.stems.size(), moved.stems.size());
  EXPECT_NE(calm.sections.positions.back(), moved.sections.positions.back());
  TreeOptions low;
  low.quality = 0.5f;
  EXPECT_LT(make_species_mesh(s, 3, low).leaves.size(), make_species_mesh(s, 3).leaves.size());
}

}  // namespace
}  // namespace sylva
