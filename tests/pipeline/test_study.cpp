// Detection studies (pipeline/study_design.h, pipeline/study.h): designs, the sun and camera they
// place, study-file errors, and runs — a resumed run and the merge of shards give the manifest of
// one run, and every frame is bit-identical rendered alone, in a shard or in a resumed run.

#include "core/error.h"
#include "pipeline/study.h"
#include "tests/support/json_parse.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace sylva {
namespace {

// A vehicle on a plane under the sun, tiny; with `trees`, one small aspen beside it.
std::string base_scene(bool trees) {
  std::string s = R"([render]
width = 20
height = 14
spp = 2
bands = ["rgb", "nir"]
max_depth = 3
[camera]
position = [0.0, -20.0, 3.0]
target = [0.0, 0.0, 1.0]
[sun]
azimuth = 150
elevation = 40
[materials.grey]
reflectance = 0.3
[materials.camo]
reflectance = { file = "spectra/target_paints.csv", column = "camouflage_green" }
[materials.metal]
reflectance = { file = "spectra/target_paints.csv", column = "painted_metal_grey" }
[materials.leaf]
type = "leaf"
prospect = { N = 1.6, Cab = 45, Car = 9, Cw = 0.012, Cm = 0.008 }
[[meshes]]
name = "ground"
shape = "plane"
size = [200, 200]
material = "grey"
class = "terrain"
[[targets]]
name = "tank"
file = "targets/vehicle.obj"
material = "camo"
label = "vehicle"
position = [0, 0, 0]
heading = 30
)";
  if (trees)
    s += R"([[trees]]
species = "../species/quaking_aspen.toml"
seed = 3
quality = 0.2
bark = "grey"
leaf = "leaf"
translate = [6, 4, 0]
)";
  return s;
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class Study : public test::TempDirTest {
 protected:
  // Writes scene.toml and study.toml (the [study] table's `output` is "out").
  StudySpec write_study(const std::string& body, bool trees = false) {
    std::ofstream(dir_ / "scene.toml") << base_scene(trees);
    std::ofstream(dir_ / "study.toml") << "[study]\nscene = \"scene.toml\"\noutput = \"out\"\n" << body;
    return load_study(dir_ / "study.toml");
  }
  std::string study_error(const std::string& body) {
    try {
      write_study(body);
    } catch (const ParseError& e) {
      return e.what();
    } catch (const Error& e) {
      return std::string("Error: ") + e.what();
    }
    return "";
  }
  StudyResult run(const StudySpec& spec, const std::filesystem::path& out, const std::string& shard = "0/1") {
    StudyRunOptions o;
    o.output_dir = out;
    std::tie(o.shard_index, o.shard_count) = parse_shard(shard);
    o.threads = 2;
    RenderObserver observer;
    return run_study(spec, o, observer);
  }
};

const std::string kGrid = R"(
[[factors]]
name = "elevation"
set = "sun.elevation"
values = [20, 60]
[[factors]]
name = "paint"
set = "targets.tank.material"
values = ["camo", "metal"]
)";

TEST_F(Study, GridListAndHypercubeDesigns) {
  const StudySpec grid = write_study(kGrid);
  const auto g = design_values(grid);
  ASSERT_EQ(g.size(), 4u);  // the first factor slowest
  EXPECT_EQ(g[0], (std::vector<std::string>{"20", "\"camo\""}));
  EXPECT_EQ(g[1], (std::vector<std::string>{"20", "\"metal\""}));
  EXPECT_EQ(g[3], (std::vector<std::string>{"60", "\"metal\""}));
  std::string list = kGrid;
  list.insert(0, "design = \"list\"\n");
  EXPECT_EQ(design_values(write_study(list)).size(), 2u);

  const std::string cube = R"(design = "latin_hypercube"
samples = 50
seed = 7
[[factors]]
name = "elevation"
set = "sun.elevation"
range = [10, 70]
[[factors]]
name = "seed"
set = "trees[0].seed"
range = [1, 1000]
integer = true
[[factors]]
name = "paint"
set = "targets.tank.material"
values = ["camo", "metal"]
)";
  const StudySpec c = write_study(cube);
  const auto v = design_values(c);
  ASSERT_EQ(v.size(), 50u);
  // One frame in each of the 50 strata of every continuous factor.
  std::set<int> strata;
  for (const auto& frame : v) strata.insert(static_cast<int>((std::stod(frame[0]) - 10.0) / 60.0 * 50.0));
  EXPECT_EQ(strata.size(), 50u);
  int camo = 0;
  for (const auto& frame : v) {
    EXPECT_EQ(frame[1].find('.'), std::string::npos) << frame[1];  // integer
    camo += frame[2] == "\"camo\"";
  }
  EXPECT_EQ(camo, 25);  // a categorical factor: stratified, so exactly half each
  EXPECT_EQ(design_values(c), v) << "the same seed, the same frames";
  StudySpec other = c;
  other.seed = 8;
  EXPECT_NE(design_values(other), v);
}

TEST_F(Study, SunFromDateTimeAndPlace) {
  // Almanac values. The equation of time at 12:00 UT: −6 min 25 s on 1980 July 27 (Duffett-Smith,
  // Practical Astronomy with your Calculator, worked example); in 2001 between −14 min 20 s (near
  // February 12) and +16 min 24 s (near November 4) (Royal Greenwich Observatory information sheet).
  EXPECT_NEAR(solar_position(0, 0, 1980, 209, 12).equation_of_time_min, -(6 + 25 / 60.0), 0.1);
  double lowest = 1e9, highest = -1e9;
  for (int day = 1; day <= 365; ++day) {
    const double eot = solar_position(0, 0, 2001, day, 12).equation_of_time_min;
    lowest = std::min(lowest, eot);
    highest = std::max(highest, eot);
  }
  EXPECT_NEAR(lowest, -(14 + 20 / 60.0), 0.15);
  EXPECT_NEAR(highest, 16 + 24 / 60.0, 0.15);
  // The 2023 March equinox (20 March, 21:24 UT) and the 2026 June solstice (21 June, 08:24 UT,
  // obliquity 23.436°): the declination then.
  EXPECT_NEAR(solar_position(0, 0, 2023, 79, 21.4).declination_deg, 0.0, 0.02);
  EXPECT_NEAR(solar_position(0, 0, 2026, 172, 8.4).declination_deg, 23.436, 0.02);
  // The sun crosses Greenwich's meridian at 12:00 UT minus the equation of time (11:43:35 UT on
  // 2001 November 3), due south and 90° − latitude + declination high.
  const SolarPosition transit = solar_position(51.4779, 0, 2001, 307, 12.0 - 16.42 / 60.0);
  EXPECT_NEAR(transit.azimuth_deg, 180.0, 0.05);
  EXPECT_NEAR(transit.elevation_deg, 90.0 - 51.4779 + transit.declination_deg, 1e-6);
  EXPECT_NEAR(transit.declination_deg, -15.0, 0.2);
  // Longitude shifts the clock: 15° east sees the same sun an hour earlier in UT.
  const SolarPosition east = solar_position(51.4779, 15, 2001, 307, 11.0 - 16.42 / 60.0);
  EXPECT_NEAR(east.azimuth_deg, 180.0, 0.05);
  // Morning and afternoon symmetric about the transit (within the day's change of declination).
  const SolarPosition morning = solar_position(45, 0, 2025, 172, 9.0);
  EXPECT_GT(morning.azimuth_deg, 60.0);
  EXPECT_LT(morning.azimuth_deg, 180.0);  // east of south in the morning
}

TEST_F(Study, SunTimeTakesClockOrMeanSolarTime) {
  // Midsummer 2025 at 45° N, 7.5° E: local mean noon is 11:30 UT, clock 13:30 in UTC+2; both put
  // the sun at the place's meridian less the equation of time (−1.9 min: the sun still east of
  // south, about 1.2° at this latitude and season).
  const std::string sun = "[[factors]]\nname = \"h\"\nvalues = [12]\n";
  const std::string place = "[sun_time]\nlatitude = 45\nlongitude = 7.5\nyear = 2025\nday = 172\n";
  const StudySpec mean = write_study(sun + place + "hour = \"h\"\n");
  const StudySpec clock = write_study(sun + place + "hour = 13.5\nutc_offset = 2\n");
  SceneOptions options;
  const SceneFile base = load_scene_file(mean.scene, options);
  const std::vector<std::string> a = plan_study(mean, base)[0].overrides, b = plan_study(clock, base)[0].overrides;
  EXPECT_EQ(a, b);
  ASSERT_EQ(a.size(), 2u);
  const SolarPosition expected = solar_position(45, 7.5, 2025, 172, 11.5);
  EXPECT_NEAR(expected.equation_of_time_min, -1.9, 0.2);
  EXPECT_NEAR(expected.azimuth_deg, 178.8, 0.2);
  EXPECT_NEAR(std::stod(a[0].substr(a[0].find('=') + 1)), expected.azimuth_deg, 1e-6) << a[0];
  EXPECT_NE(study_error("[sun_time]\nutc_offset = 1\n").find(":5: a clock time (utc_offset) needs"), std::string::npos)
      << study_error("[sun_time]\nutc_offset = 1\n");
}

TEST_F(Study, CameraOrbitAroundANamedTarget) {
  const StudySpec spec = write_study(R"(
[[factors]]
name = "range"
values = [30, 300]
[[factors]]
name = "aspect"
values = [0, 90]
[camera_orbit]
target = "tank"
range = "range"
aspect = "aspect"
elevation = 10
aim_height = 1.5
[sun_time]
latitude = 45
day = 172
hour = 12
)");
  SceneOptions options;
  const SceneFile base = load_scene_file(spec.scene, options);
  const std::vector<StudyFrame> frames = plan_study(spec, base);
  ASSERT_EQ(frames.size(), 4u);
  for (const StudyFrame& f : frames) {
    ASSERT_EQ(f.overrides.size(), 4u);
    EXPECT_EQ(f.overrides[1], "camera.target=[0, 0, 1.5]");
    EXPECT_EQ(f.overrides[2].rfind("sun.azimuth=178.8", 0), 0u) << f.overrides[2];  // noon less the EoT
  }
  // Frame 1: range 30, aspect 90 — the tank's right side: heading 30° + 90° = bearing 120°.
  SceneOptions with;
  with.overrides = frames[1].overrides;
  const SceneFile f = load_scene_file(spec.scene, with);
  const Vec3 eye = f.scene.camera.position, aim = f.scene.camera.target;
  EXPECT_NEAR(glm::length(eye - aim), 30.0f, 1e-4f);
  EXPECT_NEAR(glm::degrees(std::asin((eye.z - aim.z) / 30.0f)), 10.0f, 1e-3f);
  EXPECT_NEAR(glm::degrees(std::atan2(eye.x - aim.x, eye.y - aim.y)), 120.0f, 1e-3f);
  EXPECT_NEAR(f.scene.sun.elevation_deg, 68.44f, 0.05f);
  // Distinct inputs, distinct ids.
  std::set<std::string> ids;
  for (const StudyFrame& frame : frames) ids.insert(frame.id);
  EXPECT_EQ(ids.size(), 4u);
}

TEST_F(Study, CameraOrbitHonoursAboveTerrain) {
  // A hilly terrain and a base camera whose z are heights above it: the orbit's overrides are
  // heights too, so the loaded scene has the camera at the orbit's range and elevation.
  std::string scene = base_scene(false);
  scene.replace(scene.find("[camera]\n"), 9, "[camera]\nabove_terrain = true\n");
  scene.replace(scene.find("[[meshes]]"), std::string::npos,
                "[terrain]\nsize = [400, 400]\nresolution = 2.0\nrelief = 25.0\nfeature_size = 80\nseed = 4\n"
                "material = \"grey\"\n[[targets]]\nname = \"tank\"\nfile = \"targets/vehicle.obj\"\n"
                "material = \"camo\"\nlabel = \"vehicle\"\nposition = [10, 20, 0]\nheading = 30\n");
  std::ofstream(dir_ / "scene.toml") << scene;
  std::ofstream(dir_ / "study.toml") << "[study]\nscene = \"scene.toml\"\n[[factors]]\nname = \"aspect\"\n"
                                        "values = [0, 90, 200]\n[camera_orbit]\ntarget = \"tank\"\nrange = 120\n"
                                        "aspect = \"aspect\"\nelevation = 8\naim_height = 1.5\n";
  const StudySpec spec = load_study(dir_ / "study.toml");
  SceneOptions options;
  const SceneFile base = load_scene_file(spec.scene, options);
  ASSERT_NE(base.camera_ground, nullptr);
  const Vec3 target = base.targets[0].position;
  EXPECT_GT(std::abs(target.z), 0.5f) << "the tank stands on the hill, not at z = 0";
  std::set<float> heights;
  for (const StudyFrame& frame : plan_study(spec, base)) {
    SceneOptions with;
    with.overrides = frame.overrides;
    const SceneFile f = load_scene_file(spec.scene, with);
    const Vec3 eye = f.scene.camera.position, aim = f.scene.camera.target;
    EXPECT_NEAR(aim.z, target.z + 1.5f, 1e-3f);
    EXPECT_NEAR(glm::length(eye - aim), 120.0f, 1e-2f);
    EXPECT_NEAR(glm::degrees(std::asin((eye.z - aim.z) / 120.0f)), 8.0f, 1e-2f);
    heights.insert(eye.z - terrain_height(*base.camera_ground, Vec2(eye)));
  }
  EXPECT_EQ(heights.size(), 3u) << "the camera's height above the ground differs with the ground under it";
}

TEST_F(Study, MistakesNameTheStudyFileAndLine) {
  const std::string study = (dir_ / "study.toml").string();
  EXPECT_EQ(study_error("colour = 1\n").rfind(study + ":4: unknown key 'colour' in [study]", 0), 0u)
      << study_error("colour = 1\n");
  EXPECT_EQ(study_error("[[factors]]\nname = \"a\"\nset = \"sun.elevation\"\nrange = [1, 2]\n")
                .rfind(study + ":7: 'range' is for design = \"latin_hypercube\"", 0),
            0u);
  EXPECT_EQ(study_error("[[factors]]\nname = \"a\"\n").rfind(study + ":4: give a factor either", 0), 0u);
  EXPECT_NE(study_error("[camera_orbit]\ntarget = \"tank\"\nrange = \"far\"\n").find(":6: 'far' names no factor"),
            std::string::npos);
  EXPECT_NE(study_error("design = \"list\"\n[[factors]]\nname = \"a\"\nvalues = [1, 2]\n[[factors]]\nname = "
                        "\"b\"\nvalues = [1]\n")
                .find("the same number of values in every factor"),
            std::string::npos);
  EXPECT_NE(study_error("design = \"latin_hypercube\"\n").find(":1: a latin_hypercube needs 'samples'"),
            std::string::npos);
  EXPECT_THROW(parse_shard("2/2"), Error);
  EXPECT_THROW(parse_shard("1"), Error);
  EXPECT_EQ(parse_shard("1/3"), std::make_pair(1, 3));
}

TEST_F(Study, ResumedAndShardedRunsGiveTheManifestAndBitsOfOneRun) {
  const StudySpec spec = write_study(kGrid);
  const StudyResult one = run(spec, dir_ / "one");
  ASSERT_EQ(one.status, RenderStatus::finished);
  EXPECT_EQ(one.rendered, 4u);
  const std::string manifest = read_text(one.manifest_json), csv = read_text(one.manifest_csv);
  const test::Json j = test::JsonParser(manifest).parse();
  ASSERT_EQ(j["frames"].array.size(), 4u);
  EXPECT_EQ(j["frames"][1]["values"]["paint"].string, "\"metal\"");

  // Two shards into another folder: the same manifest, every frame the same bytes.
  EXPECT_EQ(run(spec, dir_ / "sharded", "0/2").rendered, 2u);
  EXPECT_EQ(run(spec, dir_ / "sharded", "1/2").rendered, 2u);
  EXPECT_EQ(read_text(dir_ / "sharded/manifest.json"), manifest);
  EXPECT_EQ(read_text(dir_ / "sharded/manifest.csv"), csv);
  for (const StudyFrame& f : one.frames)
    for (const char* ext : {".exr", ".json"})
      EXPECT_EQ(read_text(dir_ / "sharded/frames" / (f.id + ext)), read_text(dir_ / "one/frames" / (f.id + ext)))
          << f.id << ext;

  // Resumed: finished frames skipped, a lost one rendered again to the same bytes.
  const std::filesystem::path lost = dir_ / "one/frames" / (one.frames[2].id + ".exr");
  const std::string lost_bytes = read_text(lost);
  std::filesystem::remove(lost);
  const StudyResult resumed = run(spec, dir_ / "one");
  EXPECT_EQ(resumed.rendered, 1u);
  EXPECT_EQ(resumed.skipped, 3u);
  EXPECT_EQ(read_text(lost), lost_bytes);
  EXPECT_EQ(read_text(dir_ / "one/manifest.json"), manifest);

  // Alone: the frame's overrides given to the render call, as `sylva render --set ...` would.
  RenderCallOptions alone;
  alone.request.source = SceneSource::from_file(spec.scene.string());
  alone.request.overrides = one.frames[3].overrides;
  alone.request.threads = 1;
  alone.exr = dir_ / "alone.exr";
  RenderObserver observer;
  ASSERT_EQ(render_scene(alone, observer).status, RenderStatus::finished);
  EXPECT_EQ(read_text(dir_ / "alone.exr"), read_text(dir_ / "one/frames" / (one.frames[3].id + ".exr")));

  // Changed inputs: new ids, rendered anew, never mixed with the old frames.
  std::ofstream(dir_ / "study.toml", std::ios::app) << "[[factors]]\nname = \"azimuth\"\nset = \"sun.azimuth\"\n"
                                                       "values = [150]\n";
  const StudyResult changed = run(load_study(dir_ / "study.toml"), dir_ / "one");
  EXPECT_EQ(changed.rendered, 4u);
  for (size_t i = 0; i < 4; ++i) EXPECT_NE(changed.frames[i].id, one.frames[i].id);
}

TEST_F(Study, TheExampleStudyReads) {
  const StudySpec spec = load_study(SYLVA_SOURCE_DIR "/data/examples/study_vehicle_edge.toml");
  EXPECT_EQ(spec.scene.filename(), "targets.toml");
  EXPECT_EQ(design_values(spec).size(), 200u);
  ASSERT_TRUE(spec.camera_orbit.has_value());
  EXPECT_EQ(spec.camera_orbit->target, "camouflaged vehicle");
}

TEST_F(Study, TreesAreGeneratedOncePerStudy) {
  const StudySpec spec = write_study(kGrid, true);
  const StudyResult r = run(spec, dir_ / "out");
  EXPECT_EQ(r.rendered, 4u);
  EXPECT_EQ(r.trees_generated, 1u);  // by the base scene
  EXPECT_EQ(r.trees_reused, 4u);     // one per frame
}

}  // namespace
}  // namespace sylva
