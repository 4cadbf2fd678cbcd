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
  EXPECT_EQ(parse_scene("[render]\ninstancing = \"sweep\"\n", "s.toml", dir).scene.instance_level,
            InstanceLevel::sweep);
  try {
    parse_scene("[render]\nspp = 2\ninstancing = \"nested\"\n", "bad.toml", dir);
    FAIL() << "accepted instancing = \"nested\"";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"array\" or \"sweep\""), std::string::npos) << e.what();
  }
}

// [render] isa: Embree's kernels (RenderSettings::isa), wrong names reported at file:line.
TEST(SceneInstancing, EmbreeIsaFromTheRenderTable) {
  const char* dir = SYLVA_SOURCE_DIR "/data/examples";
  EXPECT_EQ(parse_scene("[render]\nspp = 2\n", "d.toml", dir).render.isa, EmbreeIsa::kAvx2);
  EXPECT_EQ(parse_scene("[render]\nisa = \"native\"\n", "a.toml", dir).render.isa, EmbreeIsa::kNative);
  EXPECT_EQ(parse_scene("[render]\nisa = \"avx512\"\n", "b.toml", dir).render.isa, EmbreeIsa::kAvx512);
  EXPECT_EQ(parse_scene("[render]\nisa = \"sse4.2\"\n", "s.toml", dir).render.isa, EmbreeIsa::kSse42);
  try {
    parse_scene("[render]\nspp = 2\nisa = \"avx3\"\n", "bad.toml", dir);
    FAIL() << "accepted isa = \"avx3\"";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"native\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sylva
