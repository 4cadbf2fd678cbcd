// Bands: a constant spectrum through any built-in response returns the constant, and the channel
// summaries `sylva bands` prints (centre, FWHM, equivalent width) of responses with known values.

#include "core/band.h"
#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace sylva {
namespace {

TEST(Band, ConstantSpectrumThroughEverySrfReturnsTheConstant) {
  const DenseSpectrum c = DenseSpectrum::constant(0.37f);
  for (const std::string& name : known_band_names()) {
    const Band b = resolve_band(name);
    EXPECT_FALSE(b.source.empty()) << name;
    if (name == "rgb") {
      // R, G, B of an equal-energy spectrum: its luminance (Rec.709 Y row) is the constant.
      const double y = 0.2126 * c.integral_product(b.weights[0]) + 0.7152 * c.integral_product(b.weights[1]) +
                       0.0722 * c.integral_product(b.weights[2]);
      EXPECT_NEAR(y, 0.37, 1e-4);
      continue;
    }
    ASSERT_EQ(b.weights.size(), 1u) << name;
    EXPECT_NEAR(c.integral_product(b.weights[0]), 0.37, 1e-5) << name;
  }
}

TEST(Band, SummaryOfATriangleAndABox) {
  // A triangle from 600 to 700 nm peaking at 650: centre 650, FWHM 50, equivalent width 50.
  DenseSpectrum tri;
  for (int i = 0; i < kLambdaSamples; ++i) {
    const double l = kLambdaMin + i;
    tri[i] = static_cast<float>(std::max(0.0, 1.0 - std::abs(l - 650.0) / 50.0));
  }
  const ChannelSummary t = summarise_channel(tri);
  EXPECT_NEAR(t.centre_nm, 650.0, 1e-3);
  EXPECT_NEAR(t.fwhm_nm, 50.0, 1e-3);
  EXPECT_NEAR(t.equivalent_width_nm, 50.0, 1e-3);
  // A box of 1 nm samples 800–900 nm, integrated with trapezoid edges (a 1 nm ramp each side):
  // centre 850, FWHM 101 (half maximum mid-ramp), equivalent width 101.
  DenseSpectrum box;
  for (int i = 0; i < kLambdaSamples; ++i) box[i] = (kLambdaMin + i >= 800 && kLambdaMin + i <= 900) ? 2.0f : 0.0f;
  const ChannelSummary b = summarise_channel(box);
  EXPECT_NEAR(b.centre_nm, 850.0, 1e-3);
  EXPECT_NEAR(b.fwhm_nm, 101.0, 1e-3);
  EXPECT_NEAR(b.equivalent_width_nm, 101.0, 1e-3);
}

TEST(Band, LandsatBandsAreOneWindowEach) {
  // Every Landsat 8/9 OLI band is a single pass band: its FWHM stays within the instrument's
  // widest band (SWIR2, about 190 nm) and its equivalent width agrees with it.
  for (const char* sensor : {"L8", "L9"})
    for (const char* b : {"B1", "B2", "B3", "B4", "B5", "B6", "B7", "B9"}) {
      const std::string name = std::string(sensor) + "_" + b;
      const ChannelSummary s = summarise_channel(resolve_band(name).weights[0]);
      EXPECT_LT(s.fwhm_nm, 200.0) << name;
      EXPECT_LT(s.equivalent_width_nm, 1.3 * s.fwhm_nm + 5.0) << name;
    }
}

TEST(Band, SentinelTwoCentresAreWhereEsaStatesThem) {
  // ESA's central wavelengths (S2-SRF v3.0): B4 664.6 nm, B8 832.8 nm, B8A 864.7 nm (±3 nm: ESA's
  // centre is not exactly the response-weighted mean).
  EXPECT_NEAR(summarise_channel(resolve_band("S2A_B4").weights[0]).centre_nm, 664.6, 3.0);
  EXPECT_NEAR(summarise_channel(resolve_band("S2A_B8").weights[0]).centre_nm, 832.8, 3.0);
  EXPECT_NEAR(summarise_channel(resolve_band("S2A_B8A").weights[0]).centre_nm, 864.7, 3.0);
}

namespace band_range_test {

DenseSpectrum box(double lo_nm, double hi_nm) {
  return DenseSpectrum::from_samples({lo_nm - 1e-3, lo_nm, hi_nm, hi_nm + 1e-3}, {0, 1, 1, 0}, Extrapolate::Zero);
}

std::string refusal(double lo_nm, double hi_nm) {
  try {
    make_srf_band("test", box(lo_nm, hi_nm));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace band_range_test

TEST(Band, ResponsesOutsideOrAcrossTheSpectralRangeAreRefused) {
  using band_range_test::refusal;
  // Wholly outside (a thermal band, 8–12 µm): the message names the range.
  const std::string lwir = refusal(8000, 12000);
  EXPECT_NE(lwir.find("no weight in Sylva's spectral range, 300–2500 nm"), std::string::npos) << lwir;
  EXPECT_NE(lwir.find("band 'test'"), std::string::npos) << lwir;
  // Across either end: refused, not cut off.
  const std::string swir = refusal(2200, 2700);
  EXPECT_NE(swir.find("non-zero at 2500 nm"), std::string::npos) << swir;
  const std::string uv = refusal(250, 400);
  EXPECT_NE(uv.find("non-zero at 300 nm"), std::string::npos) << uv;
  // Inside, up to the ends with zero response there: accepted.
  EXPECT_EQ(refusal(2200, 2450), "");
  EXPECT_EQ(refusal(320, 400), "");
}

}  // namespace
}  // namespace sylva
