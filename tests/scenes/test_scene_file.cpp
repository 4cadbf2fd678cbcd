// Scene files: the default scene, trees, and a clear `file:line: message` for every mistake.

#include "core/error.h"
#include "core/rng.h"
#include "geometry/leaf_shape.h"
#include "geometry/trees/lod.h"
#include "scenes/scene_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace sylva {
namespace {

const std::string kHeader = R"(
[materials.grey]
type = "diffuse"
reflectance = 0.5
)";

// Parses `text` and returns the error message ("" if it parsed).
std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "scene.toml", SYLVA_SOURCE_DIR "/data/examples");
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneFile, DefaultSceneParses) {
  const SceneFile f = default_scene();
  EXPECT_GE(f.scene.prototypes.size(), 5u);
  EXPECT_GE(f.scene.instances.size(), 8u);
  EXPECT_EQ(f.bands, (std::vector<std::string>{"rgb", "nir"}));
  EXPECT_EQ(f.content_hash.size(), 16u);
  const auto bands = resolve_bands(f, f.bands);
  EXPECT_EQ(bands.size(), 2u);
}

TEST(SceneFile, ExampleScenesParse) {
  for (const char* name : {"objects.toml", "aspen_grove.toml", "tree_models.toml", "forest_aerial.toml"}) {
    EXPECT_NO_THROW(load_scene_file(std::string(SYLVA_SOURCE_DIR) + "/data/examples/" + name)) << name;
  }
}

// The leaf quads of a scene's prototypes, with the total outline area (quad area × the shape's
// coverage) of the leaves that `instances` place.
struct PlacedLeaves {
  const LeafQuads* quads = nullptr;
  double area = 0;
};
PlacedLeaves placed_leaves(const Scene& scene) {
  PlacedLeaves out;
  for (const Instance& inst : scene.instances) {
    const LeafQuads& q = scene.prototypes[inst.prototype].leaves;
    if (q.size() == 0) continue;
    out.quads = &q;
    // The crowns are scaled uniformly: area grows with the square of the linear scale.
    const double scale = std::cbrt(std::abs(glm::determinant(Mat3(inst.world_from_object))));
    out.area += scale * scale * leaf_outline_area(q);
  }
  return out;
}

// The lines of a scene file that are not comments or blank, with their line numbers.
std::vector<std::pair<int, std::string>> scene_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::pair<int, std::string>> lines;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (!line.empty() && line[0] != '#') lines.emplace_back(n, line);
  return lines;
}

// The twin is written out in full (a scene file cannot include another), so nothing but its three
// leaf lines may differ from the grove: the camera, sun, sky, materials, trunks and instances must
// stay the grove's when either file is edited.
TEST(SceneFile, BenchGroveTwinDiffersFromTheGroveOnlyInItsLeaves) {
  const std::string dir = std::string(SYLVA_SOURCE_DIR) + "/bench/scenes/";
  const auto oval = scene_lines(dir + "dense_grove.toml"), rect = scene_lines(dir + "dense_grove_rect.toml");
  ASSERT_GT(oval.size(), 50u);
  ASSERT_EQ(oval.size(), rect.size()) << "the two files no longer have the same settings";
  const auto leaf_line = [](const std::string& l) {
    return l.starts_with("leaf_length =") || l.starts_with("leaf_width =") || l.starts_with("leaf_shape =");
  };
  int leaf_lines = 0;
  for (size_t i = 0; i < oval.size(); ++i) {
    if (leaf_line(oval[i].second) && leaf_line(rect[i].second)) {
      ++leaf_lines;
      continue;
    }
    EXPECT_EQ(oval[i].second, rect[i].second)
        << "dense_grove.toml:" << oval[i].first << " against dense_grove_rect.toml:" << rect[i].first;
  }
  EXPECT_EQ(leaf_lines, 3);
}

// bench/scenes/dense_grove_rect.toml is the grove with each oval leaf replaced by a rectangle of the
// same area at the same place: what bench/README.md's comparison of the two relies on.
TEST(SceneFile, BenchGroveTwinHasTheSameLeavesAsRectangles) {
  const std::string dir = std::string(SYLVA_SOURCE_DIR) + "/bench/scenes/";
  const SceneFile oval = load_scene_file(dir + "dense_grove.toml");
  const SceneFile rect = load_scene_file(dir + "dense_grove_rect.toml");
  const PlacedLeaves a = placed_leaves(oval.scene), b = placed_leaves(rect.scene);
  ASSERT_NE(a.quads, nullptr);
  ASSERT_NE(b.quads, nullptr);
  ASSERT_EQ(a.quads->size(), b.quads->size());
  EXPECT_EQ(a.quads->shapes.front(), LeafShape::Oval);
  EXPECT_EQ(b.quads->shapes.front(), LeafShape::Rectangle);
  // The same centres and planes, leaf by leaf.
  double worst_centre = 0, worst_normal = 0;
  for (size_t i = 0; i < a.quads->size(); ++i) {
    const Vec3* ca = &a.quads->corners[4 * i];
    const Vec3* cb = &b.quads->corners[4 * i];
    worst_centre = std::max<double>(
        worst_centre, glm::length(0.25f * (ca[0] + ca[1] + ca[2] + ca[3]) - 0.25f * (cb[0] + cb[1] + cb[2] + cb[3])));
    const Vec3 na = glm::normalize(glm::cross(ca[1] - ca[0], ca[3] - ca[0]));
    const Vec3 nb = glm::normalize(glm::cross(cb[1] - cb[0], cb[3] - cb[0]));
    worst_normal = std::max<double>(worst_normal, 1.0 - glm::dot(na, nb));
  }
  EXPECT_LT(worst_centre, 1e-5);
  EXPECT_LT(worst_normal, 1e-5);
  // Equal leaf area in the grove (the oval's coverage is a 256² grid estimate of π/4).
  EXPECT_GT(a.area, 0.0);
  EXPECT_NEAR(b.area / a.area, 1.0, 2e-3) << "oval " << a.area << " m², rectangles " << b.area << " m²";
  EXPECT_EQ(oval.scene.instances.size(), rect.scene.instances.size());
}

TEST(SceneFile, TreesShareOnePrototypePerSpeciesAndSeed) {
  const std::string text = kHeader + R"(
[[trees]]
species = "../species/quaking_aspen.toml"
seed = 3
bark = "grey"
leaf = "grey"
instances = [{ translate = [0, 0, 0] }, { translate = [5, 0, 0], object_id = 4 }]

[[trees]]
species = "../species/quaking_aspen.toml"
seed = 3
bark = "grey"
leaf = "grey"
translate = [10, 0, 0]
)";
  const SceneFile f = parse_scene(text, "trees.toml", SYLVA_SOURCE_DIR "/data/examples");
  ASSERT_EQ(f.scene.prototypes.size(), 1u);
  EXPECT_EQ(f.scene.instances.size(), 3u);
  EXPECT_EQ(f.scene.instances[1].object_id, 4u);
  EXPECT_GT(f.scene.prototypes[0].leaves.size(), 100u);
  EXPECT_GT(f.scene.prototypes[0].triangles.triangles.size(), 100u);
}

TEST(SceneFile, LeavesFalseDrawsTheStemsOnly) {
  // `leaves = false`: the same stems, no leaf quads; `leaf` may be left out; a prototype of its own.
  const std::string text = kHeader + R"(
[[trees]]
species = "../species/quaking_aspen.toml"
seed = 3
bark = "grey"
leaf = "grey"

[[trees]]
species = "../species/quaking_aspen.toml"
seed = 3
bark = "grey"
leaves = false
translate = [10, 0, 0]
)";
  const SceneFile f = parse_scene(text, "bare.toml", SYLVA_SOURCE_DIR "/data/examples");
  ASSERT_EQ(f.scene.prototypes.size(), 2u);
  EXPECT_GT(f.scene.prototypes[0].leaves.size(), 100u);
  EXPECT_EQ(f.scene.prototypes[1].leaves.size(), 0u);
  EXPECT_EQ(f.scene.prototypes[1].triangles.triangles.size(), f.scene.prototypes[0].triangles.triangles.size());
  EXPECT_NE(error_of(kHeader + "[[trees]]\nspecies = \"../species/quaking_aspen.toml\"\nbark = \"grey\"\nleaves = 1\n"),
            "");
  EXPECT_NE(error_of(kHeader + "[[trees]]\nspecies = \"../species/quaking_aspen.toml\"\nbark = \"grey\"\n"), "");
}

TEST(SceneFile, DeadBranchesGetDarkerBark) {
  // The aspen grammar flags dead branches; they become their own prototype, with the bark's
  // reflectance halved unless the entry names `dead_bark`.
  const std::string tree = R"(
[[trees]]
species = "../species/quaking_aspen.grammar"
seed = 3
bark = "grey"
leaf = "grey"
)";
  const SceneFile f = parse_scene(kHeader + tree, "dead.toml", SYLVA_SOURCE_DIR "/data/examples");
  ASSERT_EQ(f.scene.prototypes.size(), 2u);
  const Prototype& dead = f.scene.prototypes[1];
  EXPECT_GT(dead.triangles.triangles.size(), 0u);
  EXPECT_EQ(dead.leaves.size(), 0u);
  const uint32_t bark = f.scene.prototypes[0].triangle_material;
  ASSERT_NE(dead.triangle_material, bark);
  const auto& live_rho = std::get<DiffuseMaterial>(f.scene.materials[bark]).reflectance.spectrum;
  const auto& dead_rho = std::get<DiffuseMaterial>(f.scene.materials[dead.triangle_material]).reflectance.spectrum;
  for (const float lambda : {400.0f, 550.0f, 700.0f, 850.0f})
    EXPECT_FLOAT_EQ(dead_rho.eval(lambda), kDeadBarkReflectanceScale * live_rho.eval(lambda)) << lambda;

  const SceneFile named = parse_scene(kHeader + "[materials.ash]\nreflectance = 0.1\n" + tree + "dead_bark = \"ash\"\n",
                                      "dead.toml", SYLVA_SOURCE_DIR "/data/examples");
  ASSERT_EQ(named.scene.prototypes.size(), 2u);
  EXPECT_EQ(named.scene.material_names[named.scene.prototypes[1].triangle_material], "ash");
  EXPECT_EQ(named.scene.prototypes[1].triangles.triangles.size(), dead.triangles.triangles.size());

  // A tree without dead branches keeps one prototype.
  const SceneFile wp = parse_scene(kHeader + R"(
[[trees]]
species = "../species/quaking_aspen.toml"
bark = "grey"
leaf = "grey"
)",
                                   "alive.toml", SYLVA_SOURCE_DIR "/data/examples");
  EXPECT_EQ(wp.scene.prototypes.size(), 1u);
}

TEST(SceneFile, MeshFilesFromObjAndPly) {
  const auto dir = std::filesystem::temp_directory_path() / "sylva_test_scene_meshes";
  std::filesystem::create_directories(dir);
  {
    std::ofstream obj(dir / "tri.obj");
    obj << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    std::ofstream ply(dir / "tri.ply");
    ply << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  }
  const SceneFile f = parse_scene(kHeader + R"(
[[meshes]]
file = "tri.obj"
material = "grey"
object_id = 9
[[meshes]]
file = "tri.ply"
material = "grey"
translate = [0, 0, 1]
)",
                                  "meshes.toml", dir);
  ASSERT_EQ(f.scene.prototypes.size(), 2u);
  EXPECT_EQ(f.scene.prototypes[0].triangles.triangles.size(), 2u);  // the quad, fan-triangulated
  EXPECT_EQ(f.scene.prototypes[1].triangles.triangles.size(), 1u);
  EXPECT_EQ(f.scene.instances[0].object_id, 9u);
  {
    std::ofstream bad(dir / "bad.obj");
    bad << "v 0 0 0\nv 1 0 zero\n";
  }
  try {
    parse_scene(kHeader + "[[meshes]]\nfile = \"bad.obj\"\nmaterial = \"grey\"\n", "m.toml", dir);
    FAIL() << "a malformed OBJ was accepted";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj:2:"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

struct BadCase {
  const char* text;
  const char* expected;  // substring of the message, including "scene.toml:<line>:"
};

TEST(SceneFile, EveryMistakeNamesFileAndLine) {
  const BadCase cases[] = {
      {"[camera\nposition = [0, 0, 0]", "scene.toml:1:"},
      {"[camera]\nposition = [0, 0, 1]\nfov = 40\n", "scene.toml:3: unknown key 'fov' in [camera]"},
      {"[camera]\nposition = [0, 0]\n", "scene.toml:2: 'position' must be an array of 3 numbers"},
      {"[camera]\nposition = [1, 2, 3]\ntarget = [1, 2, 3]\n", "scene.toml:1: camera position and target must differ"},
      {"[camera]\nvfov = 200\n", "scene.toml:2: 'vfov' must lie in"},
      {"[camera]\ntype = \"fisheye\"\n", "scene.toml:2: camera type must be \"perspective\", \"orthographic\""},
      {"[camera]\ntype = \"orthographic\"\nvfov = 40\n", "scene.toml:3: unknown key 'vfov' in [camera]"},
      {"[render]\nspp = 0\n", "scene.toml:2: 'spp' must lie in"},
      {"[[bands]]\nname = \"lwir\"\nresponse = { lambda_nm = [8000, 12000], value = [1, 1] }\n",
       "scene.toml:3: band 'lwir': its spectral response has no weight in Sylva's spectral range, 300–2500 nm"},
      {"[[bands]]\nname = \"swir\"\nresponse = { lambda_nm = [2200, 2800], value = [1, 1] }\n",
       "scene.toml:3: band 'swir': its spectral response is non-zero at 2500 nm"},
      {"[render]\nlight_samples = 9\n", "scene.toml:2: 'light_samples' must lie in"},
      {"[render]\nwidth = \"wide\"\n", "scene.toml:2: 'width' must be an integer"},
      {"[sky]\nmodel = \"perez\"\n", "scene.toml:2: sky model must be"},
      {"[sky]\nmodel = \"uniform\"\nground_albedo = 0.2\n", "scene.toml:3: ground_albedo needs model = \"cie\""},
      {"[sky]\nground_albedo = 1.5\n", "scene.toml:2: 'ground_albedo' must lie in [0, 1]"},
      {"[sun]\nirradiance = \"moonlight\"\n", "scene.toml:2: unknown spectrum 'moonlight'"},
      {"[materials.a]\ntype = \"metal\"\n", "scene.toml:1: material type must be"},
      {"[materials.a]\ntype = \"diffuse\"\nreflectance = { file = \"nope.csv\", column = \"x\" }\n",
       "scene.toml:3: file not found: nope.csv"},
      {"[materials.a]\ntype = \"diffuse\"\nreflectance = { file = \"cie1931_2deg_cmf_1nm.csv\", column = \"wbar\" }\n",
       "no column 'wbar'"},
      {"[materials.a]\ntype = \"diffuse\"\nreflectance = { lambda_nm = [500, 400], value = [0.1, 0.2] }\n",
       "scene.toml:3: lambda_nm must increase strictly"},
      {"[materials.a]\ntype = \"leaf\"\nreflectance = 0.6\ntransmittance = 0.5\n",
       "scene.toml:1: material 'a': reflectance + transmittance = 1.1000 > 1"},
      {"[materials.a]\ntype = \"diffuse\"\nreflectance = 1.5\n",
       "scene.toml:1: material 'a': reflectance must lie in [0, 1]"},
      {"[[meshes]]\nshape = \"plane\"\nmaterial = \"missing\"\n", "scene.toml:3: unknown material 'missing'"},
      {"[materials.a]\nreflectance = 0.5\n[[meshes]]\nshape = \"torus\"\nmaterial = \"a\"\n",
       "scene.toml:4: shape must be plane, box, sphere, cylinder or leaf_cloud"},
      {"[materials.a]\nreflectance = 0.5\n[[meshes]]\nfile = \"missing.obj\"\nmaterial = \"a\"\n",
       "scene.toml:4: file not found: missing.obj"},
      {"[materials.a]\nreflectance = 0.5\n[[meshes]]\nshape = \"box\"\nmaterial = \"a\"\nscale = -1\n",
       "scene.toml:6: scale must be positive"},
      {"[materials.a]\nreflectance = 0.5\n[[trees]]\nspecies = \"../species/quaking_aspen.toml\"\nbark = \"a\"\n",
       "scene.toml:3: missing key 'leaf'"},
      {"[[bands]]\nname = \"my.band\"\nresponse = 1\n", "scene.toml:2: band name must be"},
      {"meshes = 3\n", "scene.toml:1: 'meshes' must be an array"},
      {"colour = 1\n", "scene.toml:1: unknown key 'colour' in the scene"},
      // Issue 16: these were reported without file:line, or with a wrong reason.
      {"[render]\nbands = []\n", "scene.toml:2: 'bands' needs at least one band"},
      {"[render]\nwidth = 8\nbands = [\"rgb\", \"nir\", \"rgb\"]\n", "scene.toml:3: band 'rgb' is listed twice"},
      {"[camera]\nposition = [1e30, 0, 0]\n", "scene.toml:2: camera position must lie within 1e+07 m"},
      {"[camera]\ntarget = [0, -1e30, 0]\n", "scene.toml:2: camera target must lie within 1e+07 m"},
      // Issue 9/10: haze, the Preetham sky, RGB colours.
      {"[haze]\nprofile = \"fog\"\nextinction = 0.01\n", "scene.toml:2: haze profile must be"},
      {"[haze]\nalbedo = 0.9\n", "scene.toml:1: [haze] needs exactly one of extinction"},
      {"[haze]\nextinction = 0.01\nvisibility = 100\n", "scene.toml:1: [haze] needs exactly one of extinction"},
      {"[haze]\nvisibility = 100\ng = 1\n", "scene.toml:3: 'g' must lie in"},
      {"[haze]\nvisibility = 100\nalbedo = -0.1\n", "scene.toml:3: 'albedo' must lie in [0, 1]"},
      {"[haze]\nvisibility = 100\nheight = 3\n", "scene.toml:3: unknown key 'height'"},
      {"[haze]\nvisibility = 100\ntop = 1e30\n", "scene.toml:3: a homogeneous haze needs a finite top"},
      {"[sky]\nmodel = \"preetham\"\nturbidity = 1\n", "scene.toml:3: 'turbidity' must lie in"},
      {"[sky]\nmodel = \"preetham\"\ntype = 3\n", "scene.toml:3: unknown key 'type'"},
      {"[materials.a]\nrgb = [0.2, 1.5, 0.1]\n", "scene.toml:2: rgb components must lie in [0, 1]"},
      {"[materials.a]\nrgb = [0.2, 0.5, 0.1]\nreflectance = 0.5\n", "needs a reflectance spectrum or an rgb colour"},
  };
  for (const BadCase& c : cases) {
    const std::string msg = error_of(c.text);
    EXPECT_NE(msg.find(c.expected), std::string::npos) << "input:\n" << c.text << "\nmessage: " << msg;
  }
}

// Every section family checks its own keys: a misspelt key is reported at its own line, naming
// the key, before anything else in the section is read.
TEST(SceneFile, MisspeltKeyInEverySectionNamesFileAndLine) {
  const BadCase cases[] = {
      {"[render]\nwidth = 8\nspp_ = 4\n", "scene.toml:3: unknown key 'spp_'"},
      {"[[bands]]\nname = \"b\"\nrespons = 1\n", "scene.toml:3: unknown key 'respons'"},
      {"[lod]\nbais = 2\n", "scene.toml:2: unknown key 'bais'"},
      {"[sun]\nelevation = 40\nazimut = 10\n", "scene.toml:3: unknown key 'azimut'"},
      {"[materials.a]\nreflectance = 0.5\nreflectence = 0.2\n", "scene.toml:3: unknown key 'reflectence'"},
      {"[output]\nexr = \"a.exr\"\nexpsoure = 1\n", "scene.toml:3: unknown key 'expsoure'"},
      {"[[meshes]]\nshape = \"box\"\nmaterial = \"a\"\nsegmnets = 3\n", "scene.toml:4: unknown key 'segmnets'"},
      {"[[trees]]\nspecies = \"x.toml\"\nbrak = \"a\"\n", "scene.toml:3: unknown key 'brak'"},
      {"[[placements]]\nrows = []\nspecie = {}\n", "scene.toml:3: unknown key 'specie'"},
      {"[vegetation]\nseed = 1\ntree_cvoer = 0.5\n", "scene.toml:3: unknown key 'tree_cvoer'"},
      {"[terrain]\nmaterial = \"a\"\nrelif = 3\n", "scene.toml:3: unknown key 'relif'"},
      {"[[grass]]\nmaterial = \"a\"\ndensty = 3\n", "scene.toml:3: unknown key 'densty'"},
      {"[[leaves]]\nfile = \"l.txt\"\nmaterail = \"a\"\n", "scene.toml:3: unknown key 'materail'"},
      {"[[canopies]]\ntype = \"spheres\"\nlia = 3\n", "scene.toml:3: unknown key 'lia'"},
      {"[[targets]]\nfile = \"t.obj\"\nlable = \"car\"\n", "scene.toml:3: unknown key 'lable'"},
  };
  for (const BadCase& c : cases) {
    const std::string msg = error_of(c.text);
    EXPECT_NE(msg.find(c.expected), std::string::npos) << "input:\n" << c.text << "\nmessage: " << msg;
  }
}

TEST(SceneFile, HazeSpectralSkyAndRgbColours) {
  const SceneFile f = parse_scene(R"(
[sky]
model = "preetham"
turbidity = 4.5

[haze]
profile = "exponential"
visibility = 391.2
scale_height = 50
angstrom = 1.0
g = 0.5

[materials.paint]
rgb = [0.1, 0.4, 0.8]
)",
                                  "scene.toml", SYLVA_SOURCE_DIR "/data/examples");
  const PreethamSky* sky = std::get_if<PreethamSky>(&f.scene.sky.model);
  ASSERT_NE(sky, nullptr);
  EXPECT_FLOAT_EQ(sky->turbidity, 4.5f);
  EXPECT_TRUE(sky->own_spectrum);
  const HazeDesc& h = f.scene.haze;
  EXPECT_TRUE(h.enabled);
  EXPECT_EQ(h.profile, HazeProfile::Exponential);
  EXPECT_NEAR(h.extinction_550, 0.01f, 1e-7f);
  EXPECT_FLOAT_EQ(h.scale_height, 50.0f);
  EXPECT_FLOAT_EQ(h.angstrom, 1.0f);
  EXPECT_FLOAT_EQ(h.g, 0.5f);
  EXPECT_TRUE(std::isinf(h.top));
  // Without [haze] there is none; a homogeneous haze has a 1 km top by default.
  EXPECT_FALSE(parse_scene("", "scene.toml", SYLVA_SOURCE_DIR "/data/examples").scene.haze.enabled);
  EXPECT_FLOAT_EQ(
      parse_scene("[haze]\nextinction = 0.002\n", "scene.toml", SYLVA_SOURCE_DIR "/data/examples").scene.haze.top,
      1000.0f);
  // The rgb colour became a Smits spectrum: bluish, bounded.
  const DiffuseMaterial* paint = std::get_if<DiffuseMaterial>(&f.scene.materials.back());
  ASSERT_NE(paint, nullptr);
  EXPECT_GT(paint->reflectance.spectrum.eval(450.0f), paint->reflectance.spectrum.eval(650.0f));
  EXPECT_LE(paint->reflectance.spectrum.max_value(), 1.0f);
  // A stated sky spectrum switches the Preetham sky to per-wavelength matching.
  const SceneFile stated =
      parse_scene("[sky]\nmodel = \"preetham\"\nspectrum = 0.5\n", "scene.toml", SYLVA_SOURCE_DIR "/data/examples");
  EXPECT_FALSE(std::get<PreethamSky>(stated.scene.sky.model).own_spectrum);
}

TEST(SceneFile, CustomBandsResolveBeforeBuiltIns) {
  const SceneFile f = parse_scene(R"(
[render]
bands = ["rgb", "swir_cam"]
[[bands]]
name = "swir_cam"
response = { lambda_nm = [1400, 1500, 1600, 1700], value = [0, 1, 1, 0] }
)",
                                  "bands.toml", ".");
  const auto bands = resolve_bands(f, f.bands);
  ASSERT_EQ(bands.size(), 2u);
  EXPECT_EQ(bands[1].channels[0], "swir_cam.Y");
  EXPECT_NEAR(bands[1].weights[0].integral(), 1.0, 1e-3);
  EXPECT_THROW(resolve_bands(f, {"no_such_band"}), Error);
  EXPECT_THROW(resolve_bands(f, {"rgb", "rgb"}), Error);
}

TEST(SceneFile, SentinelAndLandsatBandsAreData) {
  const SceneFile f = default_scene();
  const auto bands = resolve_bands(f, {"S2A_B8", "L8_B5", "red_edge"});
  EXPECT_EQ(bands[0].channels[0], "S2A_B8.Y");
  EXPECT_EQ(bands[1].channels[0], "L8_B5.Y");
}

}  // namespace
}  // namespace sylva

namespace sylva {
namespace {

TEST(SceneFile, MutatedAndTruncatedFilesNeverCrash) {
  // Every mutation either parses or throws a sylva::Error (ParseError for the file's own text).
  std::ifstream in(SYLVA_SOURCE_DIR "/data/examples/objects.toml");
  const std::string base((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(base.size(), 100u);
  Pcg32 rng(99);
  const char junk[] = "[]{}=\",.#\n 0123456789e-+abcxyz\t\\'";
  int parsed = 0, rejected = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::string text = base;
    switch (trial % 4) {
      case 0:
        text.resize(rng.below(static_cast<uint32_t>(text.size())));
        break;  // truncation
      case 1:
        for (int k = 0; k < 3; ++k)
          text[rng.below(static_cast<uint32_t>(text.size()))] = junk[rng.below(sizeof(junk) - 1)];
        break;
      case 2:
        text.erase(rng.below(static_cast<uint32_t>(text.size())), 1 + rng.below(40));
        break;
      default:
        text.insert(rng.below(static_cast<uint32_t>(text.size())), 1, junk[rng.below(sizeof(junk) - 1)]);
    }
    try {
      parse_scene(text, "fuzz.toml", SYLVA_SOURCE_DIR "/data/examples");
      ++parsed;
    } catch (const ParseError& e) {
      ++rejected;
      EXPECT_EQ(std::string(e.what()).rfind("fuzz.toml:", 0), 0u) << e.what();
    } catch (const Error&) {
      ++rejected;  // e.g. a band or material rejected after parsing, still a clean message
    }
  }
  EXPECT_GT(rejected, 50);
  EXPECT_GT(parsed, 10);
}

}  // namespace
}  // namespace sylva
