// Smits RGB → reflectance up-sampling (core/rgb_spectrum.h): bounded reflectance for every
// colour, and the colour it reproduces through the renderer's own rgb band and under D65 in sRGB.

#include "core/band.h"
#include "core/data_path.h"
#include "core/rgb_spectrum.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sylva {
namespace {

// Bounds on the D65/sRGB round trip, a little above the measured figures (docs/radiometry.md).
// Measured: max 0.0352 (at cyan, (0, 1, 1)), mean 0.0152, chroma < 0.5: max 0.0179.
constexpr float kD65MaxError = 0.04f;
constexpr double kD65MeanError = 0.018;
constexpr float kD65DesaturatedMaxError = 0.022f;

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

// Linear sRGB of a reflectance lit by CIE D65 (CIE 1931 2° observer, IEC 61966-2-1 matrix), white
// (reflectance 1) at (1, 1, 1).
Vec3 d65_srgb(const DenseSpectrum& reflectance) {
  static const DenseSpectrum d65 = load_spectrum(data_file("cie_d65_spd_1nm.csv"), "S_D65", Extrapolate::Zero);
  const DenseSpectrum lit = reflectance * d65;
  const double norm = d65.integral_product(cie_y());
  const double X = lit.integral_product(cie_x()) / norm, Y = lit.integral_product(cie_y()) / norm,
               Z = lit.integral_product(cie_z()) / norm;
  return Vec3(static_cast<float>(3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z),
              static_cast<float>(-0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z),
              static_cast<float>(0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z));
}

TEST(RgbSpectrum, RoundTripUnderD65InSrgb) {
  // The white point closes: reflectance 1 is sRGB white under D65.
  const Vec3 white = d65_srgb(DenseSpectrum::constant(1.0f));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(white[k], 1.0f, 2e-3f);
  // An 11 × 11 × 11 grid of linear sRGB colours through rgb_to_reflectance and back
  // (docs/radiometry.md, "RGB colours").
  float worst = 0.0f, worst_saturated = 0.0f;
  double sum = 0.0;
  int count = 0;
  Vec3 worst_colour(0.0f);
  for (int r = 0; r <= 10; ++r)
    for (int g = 0; g <= 10; ++g)
      for (int b = 0; b <= 10; ++b) {
        const Vec3 in = Vec3(r, g, b) / 10.0f;
        const Vec3 out = d65_srgb(rgb_to_reflectance(in));
        const float err = std::max({std::abs(out.x - in.x), std::abs(out.y - in.y), std::abs(out.z - in.z)});
        if (err > worst) worst_colour = in;
        worst = std::max(worst, err);
        const float chroma = std::max({in.x, in.y, in.z}) - std::min({in.x, in.y, in.z});
        if (chroma < 0.5f) worst_saturated = std::max(worst_saturated, err);
        sum += err;
        ++count;
      }
  std::printf(
      "Smits under D65/sRGB over 1331 colours: max |ΔRGB| %.4f at (%.1f %.1f %.1f), mean %.4f; "
      "colours with chroma < 0.5: max %.4f\n",
      worst, worst_colour.x, worst_colour.y, worst_colour.z, sum / count, worst_saturated);
  RecordProperty("d65_max_error", std::to_string(worst));
  RecordProperty("d65_mean_error", std::to_string(sum / count));
  EXPECT_LT(worst, kD65MaxError);
  EXPECT_LT(sum / count, kD65MeanError);
  EXPECT_LT(worst_saturated, kD65DesaturatedMaxError);
}

}  // namespace
}  // namespace sylva
