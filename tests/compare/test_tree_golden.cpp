// Geometry goldens: exact summaries (counts, bounds, leaf area, mesh hash) of the shipped species
// at fixed seeds, and `sylva tree` end to end. Regenerate the goldens after an intended change
// with `SYLVA_UPDATE_GOLDEN=1 ./test_compare --gtest_filter='*TreeGolden*'` (golden/README-geometry.md).

#include "geometry/trees/tree_stats.h"
#include "scenes/species.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace sylva {
namespace {

const std::filesystem::path kSource = SYLVA_SOURCE_DIR;

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The golden's base name: the file's stem, plus its extension for the formats that share a stem
// with a .toml species (quaking_aspen.grammar -> quaking_aspen_grammar).
std::string golden_name(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".toml" || ext == ".xml") return file.stem().string();
  return file.stem().string() + "_" + ext.substr(1);
}

struct GoldenCase {
  const char* file;
  uint64_t seed;
};

class TreeGolden : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(TreeGolden, MatchesSummary) {
  const GoldenCase c = GetParam();
  const std::filesystem::path species_file = kSource / "data" / "species" / c.file;
  const Species species = load_species(species_file);
  const TreeModel model = make_species_model(species, c.seed);
  const TreeMesh mesh = make_species_mesh(species, c.seed);
  const std::string json = tree_stats_json(compute_tree_stats(model, mesh), species.name, c.seed);
  const std::filesystem::path golden =
      kSource / "golden" / "geometry" / (golden_name(species_file) + "_seed" + std::to_string(c.seed) + ".json");
  const char* update = std::getenv("SYLVA_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    std::ofstream(golden, std::ios::binary) << json;
    GTEST_SKIP() << "updated " << golden;
  }
  ASSERT_TRUE(std::filesystem::exists(golden)) << golden << " missing; see golden/README-geometry.md";
  EXPECT_EQ(json, read_text(golden)) << "geometry changed for " << c.file << " seed " << c.seed;
}

INSTANTIATE_TEST_SUITE_P(Species, TreeGolden,
                         ::testing::Values(GoldenCase{"quaking_aspen.toml", 1}, GoldenCase{"quaking_aspen.toml", 2},
                                           GoldenCase{"black_tupelo.toml", 1}, GoldenCase{"weeping_willow.toml", 1},
                                           GoldenCase{"california_black_oak.toml", 1},
                                           GoldenCase{"quaking_aspen_arbaro.xml", 1},
                                           GoldenCase{"quaking_aspen.grammar", 1},
                                           GoldenCase{"quaking_aspen.grammar", 2},
                                           GoldenCase{"quaking_aspen.grammar", 3}, GoldenCase{"abop_bush.lsys", 1},
                                           GoldenCase{"abop_stochastic.lsys", 1}, GoldenCase{"dogwood.tmpl", 1},
                                           GoldenCase{"dogwood.tmpl", 2}, GoldenCase{"red_maple_sapling.tmpl", 1}),
                         [](const ::testing::TestParamInfo<GoldenCase>& info) {
                           std::string name = golden_name(info.param.file);
                           return name + "_seed" + std::to_string(info.param.seed);
                         });

int run(const std::string& args, const std::filesystem::path& out, const std::filesystem::path& err) {
  const std::string cmd =
      std::string("\"") + SYLVA_BINARY + "\" " + args + " > \"" + out.string() + "\" 2> \"" + err.string() + "\"";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(SylvaTree, StatsAndExport) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sylva_test_tree";
  std::filesystem::create_directories(dir);
  const std::filesystem::path out = dir / "out.txt", err = dir / "err.txt", obj = dir / "aspen.obj",
                              ply = dir / "aspen.ply";
  const std::string species = (kSource / "data" / "species" / "quaking_aspen.toml").string();
  ASSERT_EQ(
      run("tree \"" + species + "\" --seed 3 --stats --obj \"" + obj.string() + "\" --ply \"" + ply.string() + "\"",
          out, err),
      0)
      << read_text(err);
  const std::string stats = read_text(out);
  for (const char* key : {"\"stems_per_level\"", "\"clones_per_level\"", "\"leaves\"", "\"triangles\"", "\"quads\"",
                          "\"height_m\"", "\"bbox_min\"", "\"leaf_area_m2\"", "\"generation_ms\"", "\"mesh_hash\""})
    EXPECT_NE(stats.find(key), std::string::npos) << key;
  EXPECT_GT(std::filesystem::file_size(obj), 100000u);
  EXPECT_GT(std::filesystem::file_size(ply), 100000u);
  // Wind and quality are accepted; a wind changes the mesh hash.
  ASSERT_EQ(run("tree \"" + species + "\" --seed 3 --stats --time 2 --wind 5,2 --quality 0.5", dir / "wind.txt", err),
            0)
      << read_text(err);
  EXPECT_NE(read_text(dir / "wind.txt"), stats);
}

TEST(SylvaTree, SpeciesErrorsExitNonZeroWithFileAndLine) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sylva_test_tree";
  std::filesystem::create_directories(dir);
  const std::filesystem::path bad = dir / "bad.toml";
  std::ofstream(bad) << "model = \"weber-penn\"\nShape = 7\nLevles = 3\n";
  EXPECT_NE(run("tree \"" + bad.string() + "\" --stats", dir / "out.txt", dir / "err.txt"), 0);
  EXPECT_NE(read_text(dir / "err.txt").find("bad.toml:3: unknown parameter 'Levles'"), std::string::npos)
      << read_text(dir / "err.txt");
  EXPECT_NE(run("tree \"" + bad.string() + "\" --wind fast", dir / "out.txt", dir / "err.txt"), 0);
}

TEST(SylvaTree, TreeMakerTemplates) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sylva_test_tree";
  std::filesystem::create_directories(dir);
  const std::filesystem::path out = dir / "tmpl.txt", err = dir / "err.txt", obj = dir / "dogwood.obj";
  const std::string tmpl = (kSource / "data" / "species" / "dogwood.tmpl").string();
  ASSERT_EQ(run("tree \"" + tmpl + "\" --seed 1 --stats --obj \"" + obj.string() + "\"", out, err), 0)
      << read_text(err);
  EXPECT_NE(read_text(out).find("\"species\": \"dogwood\""), std::string::npos) << read_text(out);
  EXPECT_GT(std::filesystem::file_size(obj), 100000u);
  const std::filesystem::path bad = dir / "bad.tmpl";
  std::ofstream(bad) << "iterations { i= 3 }\ngravity { g= }\n";
  EXPECT_NE(run("tree \"" + bad.string() + "\" --stats", out, err), 0);
  EXPECT_NE(read_text(err).find("bad.tmpl:2: expected a number for 'g='"), std::string::npos) << read_text(err);
}

}  // namespace
}  // namespace sylva
