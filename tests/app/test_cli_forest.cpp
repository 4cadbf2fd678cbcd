// Forest scenes from the command line: a bad raster is `scene:line: raster: message`, exit 2, and
// nothing is written; a small terrain + grass scene renders.

#include "core/image.h"
#include "tests/support/json_parse.h"
#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::q;
using test::run_sylva;

// The scene with `terrain_source` as the terrain's first key.
std::string scene(const std::string& terrain_source) {
  std::string text = R"([render]
width = 48
height = 32
spp = 2
[camera]
position = [0, -6, 1.2]
target = [0, 0, 0.3]
[materials.soil]
reflectance = 0.2
[materials.grass]
type = "leaf"
prospect = { N = 1.5, Cab = 40, Car = 8, Cw = 0.01, Cm = 0.005 }
[terrain]
)";
  text += terrain_source;
  text += R"(
material = "soil"
[[grass]]
material = "grass"
density = 300
[vegetation]
grass_cover = 1.0
)";
  return text;
}

TEST(CliForest, BadRasterExitsTwoAndWritesNothing) {
  const fs::path dir = fresh_dir("cli_forest_bad");
  std::ofstream(dir / "s.toml") << scene("size = [12, 12]\nrelief = 0.5");
  std::ofstream(dir / "bad.toml") << scene("file = \"dem.png\"\nmetres_per_pixel = 0.5");
  std::string args = "render " + q(dir / "bad.toml");
  args += " -o " + q(dir / "out.exr");
  args += " --png " + q(dir / "out.png");
  args += " --quiet";
  const auto r = run_sylva(args, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.toml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("dem.png"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.exr"));
  EXPECT_FALSE(fs::exists(dir / "out.png"));

  const auto ok = run_sylva("render " + q(dir / "s.toml") + " -o " + q(dir / "out.exr") + " --quiet", dir);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const Image img = read_exr(dir / "out.exr");
  // Every pixel of the bottom row sees terrain or grass (a finite depth) lit by the sun and sky.
  const int z = img.find_channel("Z"), y = img.find_channel("G");
  ASSERT_GE(z, 0);
  ASSERT_GE(y, 0);
  for (int x = 0; x < img.width; ++x) {
    EXPECT_GT(img.at(x, img.height - 1, z), 0.0f);
    EXPECT_LT(img.at(x, img.height - 1, z), 10.0f);
    EXPECT_GT(img.at(x, img.height - 1, y), 0.0f);
  }
  fs::remove_all(dir);
}

// The OBJ of `sylva export` has no grass: it says so on stderr even with --quiet (the OBJ is not the
// whole scene; bench/compare_embree.sh reads it), and says nothing when there is no grass.
TEST(CliForest, ExportSaysGrassIsLeftOutEvenWhenQuiet) {
  const fs::path dir = fresh_dir("cli_forest_export");
  std::ofstream(dir / "s.toml") << scene("size = [12, 12]\nrelief = 0.5");
  auto r = run_sylva("export " + q(dir / "s.toml") + " --obj " + q(dir / "s.obj") + " -q", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("grass blades (curves) left out"), std::string::npos) << r.err;
  std::string bare = scene("size = [12, 12]\nrelief = 0.5");
  bare.replace(bare.find("grass_cover = 1.0"), 17, "grass_cover = 0.0");
  std::ofstream(dir / "bare.toml") << bare;
  r = run_sylva("export " + q(dir / "bare.toml") + " --obj " + q(dir / "bare.obj") + " -q", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("left out"), std::string::npos) << r.err;
}

TEST(CliForest, DefaultSceneIsAForest) {
  // `sylva render` without a scene: the four appendix species placed over procedural terrain, each
  // tree its own object id (data/examples/default.toml).
  const fs::path dir = fresh_dir("cli_forest_default");
  const auto r = run_sylva("render -o " + q(dir / "d.exr") + " --res 240x135 --spp 1 --quiet", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image img = read_exr(dir / "d.exr");
  const int id = img.find_channel("id.object");
  ASSERT_GE(id, 0);
  std::set<float> trees;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (img.at(x, y, id) > 0.0f) trees.insert(img.at(x, y, id));
  EXPECT_GE(trees.size(), 8u);  // many trees in view, told apart
  // A camouflaged vehicle stands among the trees: in view, labelled, partly hidden.
  const test::Json labels = test::parse_json(test::read_text(dir / "d.json"));
  ASSERT_EQ(labels["targets"].array.size(), 1u);
  const test::Json& target = labels["targets"][0];
  EXPECT_EQ(target["label"].string, "vehicle");
  int visible = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) visible += img.at(x, y, id) == static_cast<float>(target["object"].number);
  EXPECT_GT(visible, 0);
  EXPECT_EQ(target["visible_pixels"].number, visible);
  EXPECT_LT(target["visible_pixels"].number, target["unoccluded_pixels"].number);  // partly hidden
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sylva
