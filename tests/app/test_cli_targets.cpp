// `sylva render` with targets and placement lists: the label sidecar OUT.json written beside the
// EXR (and checked before rendering like the other outputs), and placement-list errors reported as
// file:line with exit 2 and nothing written.

#include "core/image.h"
#include "tests/support/json_parse.h"
#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <fstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::read_text;
using test::run_sylva;

// `sylva render DIR/scene.toml -o DIR/out.exr ARGS`.
test::CommandResult render_in(const fs::path& dir, const std::string& args) {
  return run_sylva("render '" + (dir / "scene.toml").string() + "' -o '" + (dir / "out.exr").string() + "' " + args,
                   dir);
}

const std::string kScene = R"([render]
width = 40
height = 30
spp = 2
[camera]
position = [0.0, -20.0, 5.0]
target = [0.0, 0.0, 2.0]
[materials.grey]
reflectance = 0.3
[materials.leaf]
type = "leaf"
reflectance = 0.4
transmittance = 0.3
[materials.camo]
reflectance = { file = "spectra/target_paints.csv", column = "camouflage_green" }
[[meshes]]
shape = "plane"
size = [200, 200]
material = "grey"
[[placements]]
file = "trees.csv"
[placements.species.aspen]
species = "species/quaking_aspen.toml"
bark = "grey"
leaf = "leaf"
quality = 0.2
[[targets]]
name = "tank"
file = "targets/vehicle.obj"
material = "camo"
label = "vehicle"
position = [0, 0, 0]
heading = 90
)";

std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(CliTargets, WritesTheLabelSidecarBesideTheExr) {
  const fs::path dir = fresh_dir("cli_targets");
  std::ofstream(dir / "scene.toml") << kScene;
  std::ofstream(dir / "trees.csv") << "x,y,species,seed,scale,heading\n-6,4,aspen,1,1,0\n6,4,aspen,2,1,30\n";
  const auto r = render_in(dir, "--quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(dir / "out.json"));
  const test::Json j = test::parse_json(read_text(dir / "out.json"));
  EXPECT_EQ(j["image"]["file"].string, "out.exr");
  ASSERT_EQ(j["targets"].array.size(), 1u);
  const test::Json& t = j["targets"][0];
  EXPECT_EQ(t["name"].string, "tank");
  // The two trees are objects 1 and 2, the target 3; its visible pixels are those of the EXR's AOV.
  EXPECT_EQ(t["object"].number, 3);
  const Image img = read_exr(dir / "out.exr");
  const int id = img.find_channel("id.object"), cls = img.find_channel("id.class");
  ASSERT_GE(cls, 0);
  EXPECT_EQ(img.types[cls], PixelType::UInt);
  int visible = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) visible += img.at(x, y, id) == 3.0f;
  EXPECT_GT(visible, 0);
  EXPECT_EQ(t["visible_pixels"].number, visible);
  ASSERT_EQ(j["variants"].array.size(), 3u);  // aspen seeds 1 and 2, the vehicle mesh
  EXPECT_EQ(j["variants"][1]["seed"].number, 2);
}

TEST(CliTargets, PlacementErrorsExitTwoAndWriteNothing) {
  const fs::path dir = fresh_dir("cli_placement_errors");
  std::ofstream(dir / "scene.toml") << kScene;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"x,y,species,seed,scale,heading\n0,0,aspen,1,1,0\n0,0,oak,1,1,0\n", "trees.csv:3: unknown species 'oak'"},
      {"x,y,species,seed,scale,heading\n0,zero,aspen,1,1,0\n", "trees.csv:2: y: expected a number"},
      {"x,y,species,seed\n", "trees.csv:1: the header needs a column 'scale'"},
  };
  for (const auto& [list, message] : cases) {
    std::ofstream(dir / "trees.csv") << list;
    const auto r = render_in(dir, "--png '" + (dir / "out.png").string() + "' --quiet");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(files_in(dir), (std::vector<std::string>{"scene.toml", "stderr.txt", "stdout.txt", "trees.csv"}));
  }
  // A broken species file named by the placements.
  std::ofstream(dir / "trees.csv") << "x,y,species,seed,scale,heading\n0,0,aspen,1,1,0\n";
  std::ofstream(dir / "broken.toml") << "model = \"weber-penn\"\nLevels = banana\n";
  std::string scene = kScene;
  scene.replace(scene.find("species/quaking_aspen.toml"), std::string("species/quaking_aspen.toml").size(),
                "broken.toml");
  std::ofstream(dir / "scene.toml") << scene;
  const auto r = render_in(dir, "--quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("broken.toml:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.exr"));
  EXPECT_FALSE(fs::exists(dir / "out.json"));
}

TEST(CliTargets, TheSidecarMayNotReplaceAnInput) {
  const fs::path dir = fresh_dir("cli_sidecar_clash");
  std::ofstream(dir / "scene.toml") << kScene;
  // The placement list is called out.json, so `-o out.exr` would replace it with the sidecar.
  std::string scene = kScene;
  scene.replace(scene.find("trees.csv"), 9, "out.json");
  std::ofstream(dir / "scene.toml") << scene;
  std::ofstream(dir / "out.json") << "x,y,species,seed,scale,heading\n0,5,aspen,1,1,0\n";
  const auto r = render_in(dir, "--quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("sidecar"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.exr"));
}

}  // namespace
}  // namespace sylva
