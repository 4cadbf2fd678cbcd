// [render] instancing: how placed copies reach Embree (Scene::instance_level), wrong values reported
// at file:line.

#include "core/error.h"
#include "scenes/scene_file.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

TEST(SceneInstancing, LevelFromTheRenderTable) {
  const char* dir = SYLVA_SOURCE_DIR "/data/examples";
  EXPECT_EQ(parse_scene("[render]\nspp = 2\n", "d.toml", dir).scene.instance_level, InstanceLevel::automatic);
  EXPECT_EQ(parse_scene("[render]\ninstancing = \"auto\"\n", "a.toml", dir).scene.instance_level,
            InstanceLevel::automatic);
  EXPECT_EQ(parse_scene("[render]\ninstancing = \"native\"\n", "n.toml", dir).scene.instance_level,
            InstanceLevel::native);
  EXPECT_EQ(parse_scene("[render]\ninstancing = \"array\"\n", "r.toml", dir).scene.instance_level,
            InstanceLevel::array);
  try {
    parse_scene("[render]\nspp = 2\ninstancing = \"nested\"\n", "bad.toml", dir);
    FAIL() << "accepted instancing = \"nested\"";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"array\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sylva
