// data/examples/emitter_furnace.toml: the emissive furnace renders to the radiance its first line
// states (a z-test of the image mean); emissive materials' parameter errors name file:line.

#include "core/error.h"
#include "render/renderer.h"
#include "scenes/scene_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

namespace sylva {
namespace {

TEST(EmitterFurnace, RendersTheRadianceItsFirstLineStates) {
  const std::string file = SYLVA_SOURCE_DIR "/data/examples/emitter_furnace.toml";
  std::ifstream in(file);
  std::string first;
  std::getline(in, first);
  const std::string key = "# expected radiance: ";
  ASSERT_EQ(first.rfind(key, 0), 0u) << first;
  const double expected = std::stod(first.substr(key.size()));

  const SceneFile f = load_scene_file(file);
  RenderSettings settings = render_settings(f);
  settings.progress = false;
  Renderer renderer(f.scene, settings);
  Film film = renderer.make_film();
  renderer.render(film);
  const Image img = renderer.make_image(film);
  int checked = 0;
  for (const Band& band : settings.bands)
    for (const std::string& channel : band.channels) {
      const int c = img.find_channel(channel), v = img.find_channel("var." + channel);
      ASSERT_GE(c, 0) << channel;
      ASSERT_GE(v, 0) << channel;
      // The pixels are independent: the mean's variance is the sum of the pixel means' variances / n².
      double sum = 0, var = 0;
      const double n = static_cast<double>(img.width) * img.height;
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
          sum += img.at(x, y, c);
          var += img.at(x, y, v);
        }
      const double mean = sum / n, se = std::sqrt(var) / n;
      ASSERT_GT(se, 0.0) << channel;
      // Two-sided z-test at α = 0.001 (|z| < 3.29); and the test has power: a 3 % error would fail.
      const double z = (mean - expected) / se;
      EXPECT_LT(std::abs(z), 3.29) << channel << ": mean " << mean << " vs " << expected << " ± " << se;
      EXPECT_GT(std::abs(mean - 1.03 * expected) / se, 3.29) << channel << ": the render cannot tell 3 % apart";
      std::printf("[emitter furnace] %s mean %.6f expected %.6f (z = %+.2f, s.e. %.2g)\n", channel.c_str(), mean,
                  expected, z, se);
      ++checked;
    }
  EXPECT_GT(checked, 0);
}

TEST(EmitterFurnace, EmissiveParameterErrorsNameTheirLine) {
  const char* dir = SYLVA_SOURCE_DIR "/data/examples";
  const auto error_of = [&](const std::string& text) -> std::string {
    try {
      parse_scene(text, "lamp.toml", dir);
    } catch (const ParseError& e) {
      return e.what();
    }
    return "accepted";
  };
  const std::string missing = error_of("[materials.lamp]\ntype = \"emissive\"\nreflectance = 0.5\n");
  EXPECT_NE(missing.find("lamp.toml:"), std::string::npos) << missing;
  EXPECT_NE(missing.find("radiance"), std::string::npos) << missing;
  const std::string negative = error_of("[materials.lamp]\ntype = \"emissive\"\nradiance = -1\n");
  EXPECT_NE(negative.find("lamp.toml:"), std::string::npos) << negative;
  EXPECT_NE(negative.find("negative"), std::string::npos) << negative;
  const std::string reflective = error_of("[materials.lamp]\ntype = \"emissive\"\nradiance = 1\nreflectance = 1.5\n");
  EXPECT_NE(reflective.find("lamp.toml:4"), std::string::npos) << reflective;
}

}  // namespace
}  // namespace sylva
