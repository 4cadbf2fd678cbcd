// Scene files with [plot], [[leaves]] and [[canopies]]: what they build, and a `file:line` message
// for every mistake (including those inside a leaf file).

#include "core/error.h"
#include "scenes/scene_file.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace sylva {
namespace {

const std::string kLeafHeader = R"(
[materials.leaf]
type = "leaf"
reflectance = 0.4
transmittance = 0.3
[materials.soil]
reflectance = 0.1
)";

std::string error_of(const std::string& text, const std::filesystem::path& dir = SYLVA_SOURCE_DIR "/data/examples") {
  try {
    parse_scene(text, "scene.toml", dir);
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(CanopyScene, HomogeneousCanopyTiledAroundThePlot) {
  const SceneFile f = parse_scene(kLeafHeader + R"(
[plot]
size = [4, 6]
centre = [1, 0]
cyclic = true
views = [[0, 0], [30, 90]]
principal_plane = [-10, 10, 10]
ground = ["soil"]
[[canopies]]
type = "homogeneous"
lai = 2
height = 1.5
disc_radius = 0.1
leaf_angles = "planophile"
material = "leaf"
tile = [3, 1]
)",
                                  "c.toml", SYLVA_SOURCE_DIR "/data/examples");
  const Scene& s = f.scene;
  EXPECT_TRUE(s.plot.defined && s.plot.cyclic);
  EXPECT_EQ(s.plot.lo, Vec2(-1, -3));
  EXPECT_EQ(s.plot.hi, Vec2(3, 3));
  ASSERT_EQ(s.prototypes.size(), 1u);
  EXPECT_EQ(s.prototypes[0].discs.size(), static_cast<size_t>(std::round(2.0 * 24 / (kPi * 0.01))));
  EXPECT_EQ(s.prototypes[0].disc_material, 0u);
  ASSERT_EQ(s.instances.size(), 3u);
  EXPECT_EQ(Vec3(s.instances[0].world_from_object[3]), Vec3(-4, 0, 0));
  EXPECT_EQ(Vec3(s.instances[2].world_from_object[3]), Vec3(4, 0, 0));
  ASSERT_EQ(f.plot.views.size(), 5u);
  EXPECT_EQ(f.plot.views[1].azimuth_deg, 90.0f);
  EXPECT_EQ(f.plot.views[2].label_deg, -10.0f);
  EXPECT_EQ(f.plot.ground_materials, std::vector<uint32_t>{1});
}

TEST(CanopyScene, SpheresAtListedOrFiledCentres) {
  const SceneFile inline_centres = parse_scene(kLeafHeader + R"(
[[canopies]]
type = "spheres"
sphere_radius = 2
lai = 1
centres = [[0, 0, 3], [5, 0, 3]]
material = "leaf"
)",
                                               "s.toml", SYLVA_SOURCE_DIR "/data/examples");
  ASSERT_EQ(inline_centres.scene.instances.size(), 2u);
  EXPECT_EQ(Vec3(inline_centres.scene.instances[1].world_from_object[3]), Vec3(5, 0, 3));
  EXPECT_EQ(inline_centres.scene.prototypes[0].discs.size(), 400u);  // LAI 1 × π 2² / (π 0.1²)
  const SceneFile het01 = parse_scene(kLeafHeader + R"(
[[canopies]]
type = "spheres"
sphere_radius = 3
lai = 1
centres_file = "../rami/rami3_het01_sphere_centres.txt"
material = "leaf"
)",
                                      "h.toml", SYLVA_SOURCE_DIR "/data/examples");
  EXPECT_EQ(het01.scene.instances.size(), 15u);
  EXPECT_EQ(het01.inputs.size(), 1u);  // the centres file is hashed with the scene
}

TEST(CanopyScene, LeafFilesAreInstancedAndTheirErrorsNameTheirLine) {
  const auto dir = std::filesystem::temp_directory_path() / ("sylva_canopy_scene_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "plot.txt") << "# radius cx cy cz nx ny nz\n0.1 0 0 1 0 0 1\n0.2 1 1 1 1 0 0\n";
  std::ofstream(dir / "bad.txt") << "0.1 0 0 1 0 0 1\n0.1 0 0 1 0 0\n";
  const SceneFile f = parse_scene(kLeafHeader + R"(
[[leaves]]
file = "plot.txt"
material = "leaf"
instances = [{ translate = [0, 0, 0] }, { translate = [10, 0, 0] }]
)",
                                  "l.toml", dir);
  ASSERT_EQ(f.scene.prototypes.size(), 1u);
  EXPECT_EQ(f.scene.prototypes[0].discs.size(), 2u);
  EXPECT_EQ(f.scene.instances.size(), 2u);
  const std::string msg = error_of(kLeafHeader + "[[leaves]]\nfile = \"bad.txt\"\nmaterial = \"leaf\"\n", dir);
  EXPECT_NE(msg.find((dir / "bad.txt").string() + ":2: expected 7 numbers"), std::string::npos) << msg;
  std::filesystem::remove_all(dir);
}

TEST(CanopyScene, EveryMistakeNamesFileAndLine) {
  const std::pair<std::string, std::string> cases[] = {
      {"[plot]\ncyclic = true\n", "scene.toml:1: [plot] needs size = [x, y]"},
      {"[plot]\nsize = [1, 1]\nviews = [[95, 0]]\n", "scene.toml:3: view zenith must be in [0, 89.9]"},
      {"[plot]\nsize = [1, 1]\nviews = [30, 0]\n", "scene.toml:3: each view is [zenith, azimuth]"},
      {"[plot]\nsize = [1, 1]\nprincipal_plane = [10, -10, 2]\n", "scene.toml:3: principal plane: expected"},
      {"[plot]\nsize = [1, 1]\nground = [\"peat\"]\n", "scene.toml:3: unknown material 'peat'"},
      {"[plot]\nsize = [1, 1]\nwalls = 1\n", "scene.toml:3: unknown key 'walls'"},
      {"[[canopies]]\ntype = \"cube\"\nmaterial = \"leaf\"\n", "scene.toml:2: canopy type must be"},
      {"[[canopies]]\ntype = \"homogeneous\"\nmaterial = \"leaf\"\n", "scene.toml:1: a homogeneous canopy needs size"},
      {"[[canopies]]\ntype = \"homogeneous\"\nsize = [1, 1]\nleaf_angles = \"plagiophile\"\nmaterial = \"leaf\"\n",
       "scene.toml:4: leaf angles must be"},
      {"[[canopies]]\ntype = \"spheres\"\nmaterial = \"leaf\"\n", "scene.toml:1: spheres need either centres"},
      {"[[canopies]]\ntype = \"spheres\"\ncentres = [[0, 0]]\nmaterial = \"leaf\"\n", "scene.toml:3: centres = "},
      {"[[canopies]]\ntype = \"spheres\"\ncentres = [[0, 0, 1]]\nheight = 2\nmaterial = \"leaf\"\n",
       "scene.toml:4: 'height' is for type = \"homogeneous\""},
      {"[[canopies]]\ntype = \"homogeneous\"\nsize = [1, 1]\nmaterial = \"leaf\"\ntile = [3, 3]\n",
       "scene.toml:5: tile needs a [plot]"},
      {"[plot]\nsize = [1, 1]\n[[canopies]]\ntype = \"homogeneous\"\nmaterial = \"leaf\"\ntile = [2, 3]\n",
       "scene.toml:6: tile counts must be odd"},
      {"[[leaves]]\nfile = \"none.txt\"\nmaterial = \"leaf\"\n", "scene.toml:2: file not found: none.txt"},
      {"[[leaves]]\nfile = \"none.txt\"\nmaterial = \"bark\"\n", "scene.toml:3: unknown material 'bark'"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string msg = error_of(kLeafHeader + text);
    // kLeafHeader is 7 lines long: shift the expected line numbers.
    const size_t colon = expected.find(':', 11);
    const int line = std::stoi(expected.substr(11, colon - 11)) + 7;
    const std::string shifted = "scene.toml:" + std::to_string(line) + expected.substr(colon);
    EXPECT_NE(msg.find(shifted), std::string::npos) << "input:\n" << text << "\nmessage: " << msg;
  }
}

}  // namespace
}  // namespace sylva
