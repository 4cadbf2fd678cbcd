// `sylva grow` end to end: outputs (OBJ, statistics, state, rings, frames), continuing a saved
// state, pruning, a grown tree in a scene, and bad input reported as file:line with exit code 2.

#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::q;
using test::read_text;
using test::run_sylva;

fs::path write_species(const fs::path& dir) {
  const fs::path p = dir / "small.toml";
  std::ofstream(p) << "model = \"hart-baker\"\nname = \"Small\"\nyears = 5\n[light]\nresolution = 96\n";
  return p;
}

TEST(CliGrow, WritesEveryOutput) {
  const fs::path dir = fresh_dir("cli_grow_outputs");
  const fs::path species = write_species(dir);
  const auto r =
      run_sylva("grow " + q(species) + " --years 6 --seed 4 --obj " + q(dir / "t.obj") + " --stats --save " +
                    q(dir / "t.hbtree") + " --rings 0.1 " + q(dir / "rings.png") + " --frames " + q(dir / "frames"),
                dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"year\": 6"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"seed\": 4"), std::string::npos);
  EXPECT_GT(fs::file_size(dir / "t.obj"), 1000u);
  EXPECT_TRUE(fs::exists(dir / "rings.png"));
  const std::string csv = read_text(dir / "rings.csv");
  EXPECT_EQ(csv.rfind("year,radius_m,", 0), 0u);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 7);  // header + one ring a year
  // One OBJ and one path-traced preview per year, and nothing else.
  int pngs = 0, objs = 0;
  for (const auto& e : fs::directory_iterator(dir / "frames")) {
    pngs += e.path().extension() == ".png";
    objs += e.path().extension() == ".obj";
  }
  EXPECT_EQ(pngs, 6);
  EXPECT_EQ(objs, 6);
  for (int y = 1; y <= 6; ++y) {
    EXPECT_TRUE(fs::exists(dir / "frames" / ("year_00" + std::to_string(y) + ".obj")));
    EXPECT_GT(fs::file_size(dir / "frames" / ("year_00" + std::to_string(y) + ".png")), 1000u);
  }
  EXPECT_EQ(read_text(dir / "t.hbtree").rfind("sylva-hart-baker-state 1\nspecies small.toml\nseed 4\nyear 6\n", 0), 0u);
  for (const auto& e : fs::directory_iterator(dir)) EXPECT_NE(e.path().filename().string().rfind(".sylva-", 0), 0u);
}

TEST(CliGrow, ASavedStateContinuesAsIfGrownInOneGo) {
  const fs::path dir = fresh_dir("cli_grow_continue");
  const fs::path species = write_species(dir);
  ASSERT_EQ(run_sylva("grow " + q(species) + " --years 4 --save " + q(dir / "a.hbtree"), dir).exit_code, 0);
  ASSERT_EQ(run_sylva("grow " + q(dir / "a.hbtree") + " --years 3 --save " + q(dir / "b.hbtree"), dir).exit_code, 0);
  ASSERT_EQ(run_sylva("grow " + q(species) + " --years 7 --save " + q(dir / "c.hbtree"), dir).exit_code, 0);
  EXPECT_EQ(read_text(dir / "b.hbtree"), read_text(dir / "c.hbtree"));
  // Pruning a branch between years changes what grows after it.
  const auto pruned =
      run_sylva("grow " + q(dir / "a.hbtree") + " --prune 2 --years 3 --save " + q(dir / "p.hbtree"), dir);
  ASSERT_EQ(pruned.exit_code, 0) << pruned.err;
  EXPECT_NE(read_text(dir / "p.hbtree"), read_text(dir / "b.hbtree"));
}

TEST(CliGrow, AGrownTreeIsASceneSpecies) {
  const fs::path dir = fresh_dir("cli_grow_scene");
  const fs::path species = write_species(dir);
  ASSERT_EQ(run_sylva("grow " + q(species) + " --years 3 --save " + q(dir / "t.hbtree"), dir).exit_code, 0);
  std::ofstream(dir / "scene.toml") << "[materials.bark]\ntype = \"diffuse\"\nreflectance = 0.3\n"
                                       "[materials.leaf]\ntype = \"leaf\"\nreflectance = 0.1\ntransmittance = 0.1\n"
                                       "[[trees]]\nspecies = \"t.hbtree\"\nbark = \"bark\"\nleaf = \"leaf\"\n"
                                       "[[trees]]\nspecies = \"small.toml\"\nbark = \"bark\"\nleaf = \"leaf\"\n"
                                       "translate = [3, 0, 0]\n";
  const auto r = run_sylva("export " + q(dir / "scene.toml") + " --obj " + q(dir / "scene.obj"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(fs::file_size(dir / "scene.obj"), 1000u);
  // The same scene as obstacles: the tree grows beside them.
  const auto beside = run_sylva("grow " + q(species) + " --years 2 --obstacles " + q(dir / "scene.toml"), dir);
  EXPECT_EQ(beside.exit_code, 0) << beside.err;
}

TEST(CliGrow, BadInputIsFileLineAndExitTwo) {
  const fs::path dir = fresh_dir("cli_grow_bad");
  std::ofstream(dir / "typo.toml") << "model = \"hart-baker\"\nyears = 3\nbud_brake = 0.5\n";
  auto r = run_sylva("grow " + q(dir / "typo.toml") + " --obj " + q(dir / "o.obj"), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("typo.toml:3: unknown key 'bud_brake'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o.obj"));

  std::ofstream(dir / "wp.toml") << "model = \"weber-penn\"\n";
  r = run_sylva("grow " + q(dir / "wp.toml"), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("needs a Hart-Baker species"), std::string::npos) << r.err;

  const fs::path species = write_species(dir);
  ASSERT_EQ(run_sylva("grow " + q(species) + " --years 2 --save " + q(dir / "s.hbtree"), dir).exit_code, 0);
  std::string state = read_text(dir / "s.hbtree");
  state.replace(state.find("year 2"), 6, "year x");
  std::ofstream(dir / "broken.hbtree") << state;
  r = run_sylva("grow " + q(dir / "broken.hbtree") + " --years 1", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("broken.hbtree:4: expected a whole number"), std::string::npos) << r.err;

  r = run_sylva("grow " + q(dir / "s.hbtree") + " --prune 0", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("prune"), std::string::npos) << r.err;
  r = run_sylva("grow " + q(dir / "s.hbtree") + " --rings 500 " + q(dir / "r.png"), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "r.png"));
  r = run_sylva("grow " + q(species) + " --years -3", dir);
  EXPECT_EQ(r.exit_code, 2);

  // A frames directory that is a file, or lies under one, is refused before anything is grown.
  std::ofstream(dir / "plain_file") << "x";
  for (const fs::path& frames : {dir / "plain_file", dir / "plain_file" / "sub"}) {
    r = run_sylva("grow " + q(species) + " --years 2 --frames " + q(frames) + " --save " + q(dir / "f.hbtree"), dir);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--frames"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "f.hbtree"));
  }
}

}  // namespace
}  // namespace sylva
