// `--set section.key=value` overrides (SceneOptions::overrides, scenes/toml_reader.h): applied to
// the parsed TOML before the sections read it, and every mistake named after the override.

#include "core/error.h"
#include "scenes/scene_file.h"

#include "tests/support/box_scene.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

namespace sylva {
namespace {

const std::string kScene = test::kBoxSceneToml;

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
  EXPECT_EQ(f.render.height, 16);
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

TEST(SceneOverrides, WrongTypesNameTheOverrideAndTheKey) {
  const std::pair<const char*, const char*> cases[] = {
      {"render.width=1.5", "--set render.width=1.5: 'width' must be an integer"},
      {"render.width=\"wide\"", "--set render.width=\"wide\": 'width' must be an integer"},
      {"camera.position=3", "--set camera.position=3: 'position' must be an array"},
      {"camera.position=[1, 2]", "--set camera.position=[1, 2]: 'position' must be an array of 3 numbers"},
      {"sun.elevation=[10]", "--set sun.elevation=[10]: 'elevation' must be a number"},
      {"meshes[0].material=3", "--set meshes[0].material=3: 'material' must be a string"},
      {"sun=3", "--set sun=3: '"},
  };
  for (const auto& [override, expected] : cases) {
    const std::string e = error_with({override});
    EXPECT_EQ(e.rfind(expected, 0), 0u) << override << " gave: " << e;
  }
}

// Entries of a list of tables by their `name`: `meshes.box.size`, or quoted, `meshes."the box".size`.
TEST(SceneOverrides, ListEntriesByName) {
  const std::string named = kScene + "name = \"the box\"\n";
  const auto parse_named = [&](const std::vector<std::string>& overrides) {
    SceneOptions options;
    options.overrides = overrides;
    return parse_scene(named, "scene.toml", SYLVA_SOURCE_DIR "/data/examples", options);
  };
  const auto error_named = [&](const std::vector<std::string>& overrides) -> std::string {
    try {
      parse_named(overrides);
    } catch (const ParseError& e) {
      return e.what();
    }
    return "";
  };
  const SceneFile by_index = parse_named({"meshes[1].translate=[3, 0, 0]"});
  const SceneFile by_name = parse_named({"meshes.\"the box\".translate=[3, 0, 0]"});
  EXPECT_EQ(by_name.scene.instances[1].world_from_object, by_index.scene.instances[1].world_from_object);
  EXPECT_FLOAT_EQ(by_name.scene.instances[1].world_from_object[3].x, 3.0f);
  EXPECT_EQ(error_named({"meshes.lorry.size=1"}),
            "--set meshes.lorry.size=1: no [[meshes]] entry has name = 'lorry' (names: 'the box')");
  EXPECT_EQ(error_named({"meshes.\"the box\".sise=1"}).rfind("--set meshes.\"the box\".sise=1: unknown key 'sise'", 0),
            0u);
  EXPECT_EQ(error_named({"meshes.\"the box\"=1"}),
            "--set meshes.\"the box\"=1: give a key of the [[meshes]] entry, e.g. .name=...");
  EXPECT_EQ(error_named({"sun.\"x\"=1"}),
            "--set sun.\"x\"=1: a quoted name must follow a list of tables, as in targets.\"x\"");
  EXPECT_EQ(error_named({"meshes.\"the box.size=1"}).rfind("--set meshes.\"the box.size=1: unterminated quote", 0), 0u);
  const std::string twice = kScene + "name = \"b\"\n[[meshes]]\nshape = \"box\"\nmaterial = \"grey\"\nname = \"b\"\n";
  SceneOptions options;
  options.overrides = {"meshes.b.size=1"};
  try {
    parse_scene(twice, "scene.toml", SYLVA_SOURCE_DIR "/data/examples", options);
    ADD_FAILURE() << "two entries named b";
  } catch (const ParseError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--set meshes.b.size=1: 2 [[meshes]] entries have name = 'b': index one instead (meshes[0], ...)");
  }
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
