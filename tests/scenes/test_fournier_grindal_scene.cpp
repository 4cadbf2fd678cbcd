// Fournier–Grindal species in scenes: the TOML species reader's `model = "fournier-grindal"`,
// parameter errors with file:line, [[trees]] placement as one prototype of solids beside other
// models, the species palettes as default materials, and the turbid crown's need for `leaf`.

#include "core/error.h"
#include "scenes/scene_file.h"
#include "scenes/species.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace sylva {
namespace {

const std::filesystem::path kSource = SYLVA_SOURCE_DIR;

std::string species_error(const std::string& text) {
  try {
    parse_species(text, "bad.toml");
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(FournierGrindalSpecies, ShippedSpeciesParseAndGenerate) {
  for (const char* file : {"fg_poplar.toml", "fg_round.toml", "fg_conifer.toml", "fg_round_turbid.toml"}) {
    const Species s = load_species(kSource / "data" / "species" / file);
    ASSERT_TRUE(std::holds_alternative<FournierGrindalParams>(s.model)) << file;
    const TreeModel m = make_species_model(s, 1);
    ASSERT_EQ(m.solids.size(), 2u) << file;
    EXPECT_GT(m.solids[1].planes.size(), 6u) << file;
  }
  // The poplar's long initial normal gives a crown taller than wide (§2.1).
  const TreeModel poplar = make_species_model(load_species(kSource / "data" / "species" / "fg_poplar.toml"), 1);
  const Bounds3& b = poplar.solids[1].bounds;
  EXPECT_GT(b.hi.z - b.lo.z, 2.0f * (b.hi.x - b.lo.x));
}

TEST(FournierGrindalSpecies, ErrorsCarryFileAndLine) {
  const std::string head = "model = \"fournier-grindal\"\n";
  EXPECT_EQ(species_error(head), "bad.toml:1: a fournier-grindal species needs 'normals' (x, y, z triples, metres)");
  EXPECT_EQ(species_error(head + "normals = [1, 0, 0, 0, 1]\n"),
            "bad.toml:2: 'normals' must list x, y, z triples (a multiple of 3 numbers)");
  EXPECT_EQ(
      species_error(head + "normals = [1, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, -1]\nmu_alpha = 95\n").find("bad.toml:3:"),
      0u);
  EXPECT_EQ(
      species_error(head + "normals = [1, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, -1]\noptics = \"fog\"\n").find("bad.toml:3:"),
      0u);
  EXPECT_NE(species_error(head + "normals = [1, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, -1]\nmu_alfa = 20\n").find("mu_alfa"),
            std::string::npos);
}

TEST(FournierGrindalScene, CrownsBesideWeberPennTrees) {
  const SceneFile f = parse_scene(R"(
[materials.grey]
reflectance = 0.5

[[trees]]
species = "../species/fg_round.toml"
seed = 3
instances = [{ translate = [0, 0, 0] }, { translate = [9, 0, 0], rotate = [0, 0, 40] }]

[[trees]]
species = "../species/quaking_aspen.toml"
bark = "grey"
leaf = "grey"
translate = [-8, 0, 0]
)",
                                  "crowns.toml", kSource / "data" / "examples");
  ASSERT_EQ(f.scene.instances.size(), 3u);
  const Prototype& crown = f.scene.prototypes[f.scene.instances[0].prototype];
  EXPECT_EQ(f.scene.instances[0].prototype, f.scene.instances[1].prototype);  // one prototype, instanced
  ASSERT_EQ(crown.solids.size(), 2u);
  ASSERT_EQ(crown.solid_palettes.size(), 2u);
  EXPECT_EQ(crown.solid_palettes[0].size(), size_t(kFournierGrindalBarkColours));  // §5 bark draws
  EXPECT_EQ(crown.solid_palettes[1].size(), 4u);                                   // the species' crown colours
  const Prototype& aspen = f.scene.prototypes[f.scene.instances[2].prototype];
  EXPECT_GT(aspen.triangles.triangles.size(), 1000u);
  EXPECT_TRUE(aspen.solids.empty());
}

TEST(FournierGrindalScene, TurbidCrownNeedsLeafMaterial) {
  const std::string tree = "[[trees]]\nspecies = \"../species/fg_round_turbid.toml\"\n";
  try {
    parse_scene(tree, "s.toml", kSource / "data" / "examples");
    ADD_FAILURE() << "a turbid crown without 'leaf' was accepted";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("needs 'leaf'"), std::string::npos) << e.what();
  }
  const SceneFile f =
      parse_scene("[materials.l]\ntype = \"leaf\"\nreflectance = 0.4\ntransmittance = 0.4\n" + tree + "leaf = \"l\"\n",
                  "s.toml", kSource / "data" / "examples");
  const Prototype& p = f.scene.prototypes.at(0);
  EXPECT_GT(p.solids[1].leaf_area_density, 0.0f);
  EXPECT_EQ(p.solid_palettes[1].size(), 1u);
}

}  // namespace
}  // namespace sylva
