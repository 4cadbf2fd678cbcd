// Smits RGB → reflectance up-sampling (core/rgb_spectrum.h): bounded reflectance for every
// colour, and the colour it reproduces through the renderer's own rgb band.

#include "core/band.h"
#include "core/rgb_spectrum.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sylva {
namespace {

// The rgb band's channels for a reflectance, white-balanced so reflectance 1 gives (1, 1, 1): the
// colour an equal-energy white light shows on the surface.
Vec3 band_rgb(const Band& rgb, const DenseSpectrum& reflectance) {
  const DenseSpectrum one = DenseSpectrum::constant(1.0f);
  Vec3 c;
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<float>(reflectance.integral_product(rgb.weights[static_cast<size_t>(k)]) /
                              one.integral_product(rgb.weights[static_cast<size_t>(k)]));
  return c;
}

TEST(RgbSpectrum, ReflectanceStaysInUnitInterval) {
  for (int r = 0; r <= 8; ++r)
    for (int g = 0; g <= 8; ++g)
      for (int b = 0; b <= 8; ++b) {
        const DenseSpectrum s = rgb_to_reflectance(Vec3(r, g, b) / 8.0f);
        EXPECT_GE(s.min_value(), 0.0f) << r << g << b;
        EXPECT_LE(s.max_value(), 1.0f) << r << g << b;
      }
  // Out-of-range input is clamped, not extrapolated.
  EXPECT_LE(rgb_to_reflectance(Vec3(3.0f, -1.0f, 0.5f)).max_value(), 1.0f);
  EXPECT_GE(rgb_to_reflectance(Vec3(3.0f, -1.0f, 0.5f)).min_value(), 0.0f);
}

TEST(RgbSpectrum, GreysAreFlat) {
  for (const float v : {0.0f, 0.2f, 0.5f, 1.0f}) {
    const DenseSpectrum s = rgb_to_reflectance(Vec3(v));
    EXPECT_NEAR(s.min_value(), v, 1e-3f * (1.0f + v));
    EXPECT_NEAR(s.max_value(), v, 1e-6f + 1e-3f * v);
  }
}

TEST(RgbSpectrum, RoundTripThroughTheRgbBand) {
  const Band rgb = make_rgb_band();
  float worst = 0.0f, sum = 0.0f;
  int count = 0;
  for (int r = 0; r <= 4; ++r)
    for (int g = 0; g <= 4; ++g)
      for (int b = 0; b <= 4; ++b) {
        const Vec3 in = Vec3(r, g, b) / 4.0f;
        const Vec3 out = band_rgb(rgb, rgb_to_reflectance(in));
        const float err = std::max({std::abs(out.x - in.x), std::abs(out.y - in.y), std::abs(out.z - in.z)});
        worst = std::max(worst, err);
        sum += err;
        ++count;
      }
  std::printf("Smits round trip over 125 colours: max |ΔRGB| %.4f, mean %.4f\n", worst, sum / count);
  RecordProperty("max_error", std::to_string(worst));
  // Smits's bases reproduce the primaries to a few percent; saturated colours lose the most.
  EXPECT_LT(worst, 0.05f);
  EXPECT_LT(sum / count, 0.02f);
  // Hue is kept: a saturated green stays green-dominant.
  const Vec3 green = band_rgb(rgb, rgb_to_reflectance(Vec3(0.0f, 0.6f, 0.0f)));
  EXPECT_GT(green.y, 3.0f * std::max(green.x, green.z));
}

}  // namespace
}  // namespace sylva
