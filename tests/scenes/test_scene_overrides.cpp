// `--set section.key=value` overrides (SceneOptions::overrides, scenes/toml_reader.h): applied to
// the parsed TOML before the sections read it, and every mistake named after the override.

#include "core/error.h"
#include "scenes/scene_file.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace sylva {
namespace {

const std::string kScene = R"([render]
width = 32
height = 24

[camera]
position = [0.0, -6.0, 4.0]
target = [0.0, 0.0, 0.0]

[sun]
azimuth = 210
elevation = 35

[materials.grey]
reflectance = 0.4

[[meshes]]
shape = "plane"
size = [40, 40]
material = "grey"

[[meshes]]
shape = "box"
size = [1.0, 1.0, 1.2]
material = "grey"
)";

SceneFile parse_with(const std::vector<std::string>& overrides) {
  SceneOptions options;
  options.overrides = overrides;
  return parse_scene(kScene, "scene.toml", SYLVA_SOURCE_DIR "/data/examples", options);
}

std::string error_with(const std::vector<std::string>& overrides) {
  try {
    parse_with(overrides);
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneOverrides, ReplaceAKeyOfASection) {
  const SceneFile plain = parse_with({});
  const SceneFile f = parse_with({"sun.elevation=10", "render.width=48"});
  EXPECT_FLOAT_EQ(plain.scene.sun.elevation_deg, 35.0f);
  EXPECT_FLOAT_EQ(f.scene.sun.elevation_deg, 10.0f);
  EXPECT_FLOAT_EQ(f.scene.sun.azimuth_deg, 210.0f);  // the rest of [sun] is kept
  EXPECT_EQ(f.render.width, 48);
  EXPECT_EQ(f.render.height, 24);
}

TEST(SceneOverrides, ArraysTablesAndBareWords) {
  const SceneFile f = parse_with({"camera.position=[1, -9, 2.5]", "output.view=ACES", "output.exposure = -1.5"});
  EXPECT_FLOAT_EQ(f.scene.camera.position.x, 1.0f);
  EXPECT_FLOAT_EQ(f.scene.camera.position.y, -9.0f);
  EXPECT_FLOAT_EQ(f.scene.camera.position.z, 2.5f);
  EXPECT_EQ(f.output.view, "ACES");  // a bare word is a string; [output] did not exist in the file
  EXPECT_FLOAT_EQ(f.output.exposure_ev, -1.5f);
}

TEST(SceneOverrides, IndexIntoAListOfTables) {
  const SceneFile plain = parse_with({});
  const SceneFile f = parse_with({"meshes[1].size=[2.0, 2.0, 2.4]"});
  ASSERT_EQ(f.scene.instances.size(), plain.scene.instances.size());
  EXPECT_NE(f.content_hash, plain.content_hash);
  EXPECT_EQ(error_with({"meshes[1].size=[2.0, 2.0, 2.4]"}), "");
  EXPECT_EQ(error_with({"meshes[2].size=1"}), "--set meshes[2].size=1: [[meshes]] has 2 entries (indices from 0)");
  EXPECT_EQ(error_with({"sun[0].elevation=1"}),
            "--set sun[0].elevation=1: there is no list of tables [[sun]] to index");
  EXPECT_EQ(error_with({"meshes[0]=1"}), "--set meshes[0]=1: give a key of meshes[0], e.g. meshes[0].name=...");
}

TEST(SceneOverrides, MisspeltKeysAndSectionsNameTheOverride) {
  const std::string key = error_with({"sun.elevaton=10"});
  EXPECT_EQ(key.rfind("--set sun.elevaton=10: unknown key 'elevaton' in [sun]", 0), 0u) << key;
  const std::string section = error_with({"sunn.elevation=10"});
  EXPECT_EQ(section.rfind("--set sunn.elevation=10: unknown key 'sunn'", 0), 0u) << section;
  const std::string nested = error_with({"meshes[0].sise=3"});
  EXPECT_EQ(nested.rfind("--set meshes[0].sise=3: unknown key 'sise'", 0), 0u) << nested;
  // The same mistake in the file is reported at its line, as before.
  EXPECT_EQ(error_with({}), "");
}

TEST(SceneOverrides, BadValuesNameTheOverride) {
  const std::string word = error_with({"sun.elevation=high"});
  EXPECT_EQ(word.rfind("--set sun.elevation=high: ", 0), 0u) << word;
  EXPECT_NE(word.find("elevation"), std::string::npos) << word;
  const std::string range = error_with({"sun.elevation=200"});
  EXPECT_EQ(range.rfind("--set sun.elevation=200: ", 0), 0u) << range;
  const std::string toml = error_with({"camera.position=[1, 2"});
  EXPECT_EQ(toml.rfind("--set camera.position=[1, 2: '[1, 2' is not a TOML value", 0), 0u) << toml;
  EXPECT_EQ(error_with({"sun.elevation"}), "--set sun.elevation: expected SECTION.KEY=VALUE, e.g. sun.elevation=10");
  EXPECT_EQ(error_with({"=3"}).rfind("--set =3: ", 0), 0u);
  EXPECT_EQ(error_with({"sun..x=3"}).rfind("--set sun..x=3: ", 0), 0u);
  EXPECT_EQ(error_with({"sun.elevation=1\nx=2"}), "--set sun.elevation=1\nx=2: an override is one line");
}

TEST(SceneOverrides, ChangeTheContentHashInOrder) {
  const std::string plain = parse_with({}).content_hash;
  const std::string a = parse_with({"sun.elevation=10"}).content_hash;
  EXPECT_NE(a, plain);
  EXPECT_EQ(parse_with({"sun.elevation=10"}).content_hash, a);
  EXPECT_NE(parse_with({"sun.elevation=10", "sun.elevation=20"}).content_hash,
            parse_with({"sun.elevation=20", "sun.elevation=10"}).content_hash);
  // The last of two overrides of one key wins.
  EXPECT_FLOAT_EQ(parse_with({"sun.elevation=10", "sun.elevation=20"}).scene.sun.elevation_deg, 20.0f);
}

}  // namespace
}  // namespace sylva
