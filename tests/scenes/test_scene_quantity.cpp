// [render] quantity: parsed into the render settings, wrong values reported at file:line.

#include "core/error.h"
#include "scenes/scene_file.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

TEST(SceneQuantity, ReflectanceFromTheRenderTable) {
  const SceneFile f =
      parse_scene("[render]\nquantity = \"reflectance\"\n", "q.toml", SYLVA_SOURCE_DIR "/data/examples");
  EXPECT_EQ(render_settings(f).quantity, Quantity::reflectance);
  const SceneFile d = parse_scene("[render]\nspp = 2\n", "d.toml", SYLVA_SOURCE_DIR "/data/examples");
  EXPECT_EQ(render_settings(d).quantity, Quantity::radiance);
  try {
    parse_scene("[render]\nspp = 2\nquantity = \"brf\"\n", "bad.toml", SYLVA_SOURCE_DIR "/data/examples");
    FAIL() << "accepted quantity = \"brf\"";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("reflectance"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sylva
