// Statistical image comparison (compare/image_compare.h) and its report (compare/compare_report.h).
// The power tests draw synthetic Monte Carlo estimates: a pixel mean with spp samples of per-sample
// standard deviation σ is Gaussian, mean μ, variance σ²/spp, and its estimated variance is
// σ²/spp · χ²(spp−1)/(spp−1). Fixed seeds; the thresholds leave a wide statistical margin.

#include "compare/compare_report.h"
#include "compare/image_compare.h"
#include "core/error.h"
#include "core/image.h"
#include "tests/support/atomic_temporaries.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;

constexpr int kSize = 64;

// A structured mean: 4-pixel blocks of two levels over a smooth gradient, different per channel.
float structured_mean(int x, int y, int c) {
  const bool block = ((x / 4) + (y / 4) + c) % 2 == 0;
  return (block ? 0.8f : 0.2f) + 0.1f * static_cast<float>(x + y) / kSize;
}

struct Draw {
  int spp = 64;
  float rel_sigma = 0.5f;  // per-sample σ as a fraction of μ
  float scale = 1.0f;      // multiplies μ (a biased renderer)
  int shift_x = 0;         // samples μ(x − shift_x, y) (a shifted camera)
  int patch = 0;           // > 0: `scale` applies only to the patch × patch square at (16, 16)
  bool variance_layer = true;
};

Draw draw(int spp, float rel_sigma = 0.5f, float scale = 1.0f, int shift_x = 0, bool variance_layer = true) {
  Draw d;
  d.spp = spp;
  d.rel_sigma = rel_sigma;
  d.scale = scale;
  d.shift_x = shift_x;
  d.variance_layer = variance_layer;
  return d;
}

// An image with channels R,G,B (and var.R, var.G, var.B) drawn as described at the top.
Image draw_image(const Draw& d, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::gamma_distribution<double> chi2_half((d.spp - 1) / 2.0, 2.0);  // χ²(spp−1)
  Image image = make_image(kSize, kSize, {"R", "G", "B"});
  if (d.variance_layer)
    for (const char* v : {"var.R", "var.G", "var.B"}) image.add_channel(v, PixelType::Float);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < 3; ++c) {
        const bool scaled = d.patch == 0 || (x >= 16 && x < 16 + d.patch && y >= 16 && y < 16 + d.patch);
        const double mu = (scaled ? d.scale : 1.0f) * structured_mean(std::clamp(x - d.shift_x, 0, kSize - 1), y, c);
        const double var_mean = std::pow(d.rel_sigma * mu, 2) / d.spp;
        image.at(x, y, c) = static_cast<float>(mu + normal(rng) * std::sqrt(var_mean));
        const double estimate = var_mean * chi2_half(rng) / (d.spp - 1);
        if (d.variance_layer) image.at(x, y, 3 + c) = static_cast<float>(estimate);
      }
  image.attributes = {{"sylva:spp", std::to_string(d.spp)}};
  return image;
}

const Draw kReference = draw(4096);
const Draw kTest = draw(64);

TEST(ImageCompare, SidakLevelAndNormalQuantiles) {
  EXPECT_NEAR(two_sided_p(1.959964), 0.05, 1e-6);
  EXPECT_NEAR(two_sided_z(0.05), 1.959964, 1e-5);
  EXPECT_NEAR(two_sided_z(1e-6), 4.891638, 1e-5);
  const Image ref = draw_image(kReference, 1), test = draw_image(kTest, 2);
  const CompareResult r = compare_images(test, ref, {});
  const double n = 3.0 * kSize * kSize;
  EXPECT_NEAR(r.alpha_pixel, 1.0 - std::pow(0.99, 1.0 / n), 1e-12);
  EXPECT_NEAR(r.alpha_pixel, 8.179e-7, 1e-9);
  EXPECT_NEAR(two_sided_p(r.z_critical), r.alpha_pixel, 1e-12);
  EXPECT_EQ(r.tested, static_cast<int64_t>(n));
}

TEST(ImageCompare, SameDistributionPassesInNearlyAllTrials) {
  constexpr int kTrials = 40;
  int passes = 0;
  double worst_share = 0.0, worst_bias = 0.0, worst_tile = 0.0;
  for (int t = 0; t < kTrials; ++t) {
    const Image ref = draw_image(kReference, 1000 + t), test = draw_image(kTest, 2000 + t);
    const CompareResult r = compare_images(test, ref, {});
    passes += r.passed ? 1 : 0;
    worst_share = std::max(worst_share, r.reject_fraction);
    for (const ChannelReport& c : r.channels) {
      worst_bias = std::max(worst_bias, std::abs(c.bias_z));
      worst_tile = std::max(worst_tile, std::abs(c.tile_z));
    }
  }
  std::cout << "same distribution (64 vs 4096 spp): " << passes << "/" << kTrials << " pass, worst rejecting share "
            << 100.0 * worst_share << "%, worst |bias z| " << worst_bias << ", worst |tile z| " << worst_tile << "\n";
  EXPECT_GE(passes, kTrials - 1);  // nominal false-failure rate ≈ 1% + 0.1%
  EXPECT_LT(worst_share, 0.0025);
}

TEST(ImageCompare, ChannelMismatchQuotesNamesOnOneLine) {
  // Channel names come from the files: a corrupt one can hold a line break.
  const Image test = make_image(2, 2, {"R", "bad\nname"});
  const Image ref = make_image(2, 2, {"R", "G"});
  try {
    compare_images(test, ref, {});
    FAIL() << "channel mismatch not reported";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("only in test: bad\\x0aname"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(ImageCompare, ThreePercentShiftFails) {
  // Low spp: no single pixel can see 3% (z ≈ 0.5), the mean-bias test does (z ≈ 30).
  {
    Draw biased = kTest;
    biased.scale = 1.03f;
    const CompareResult r = compare_images(draw_image(biased, 7), draw_image(kReference, 8), {});
    std::cout << "+3% at 64 spp: rejecting share " << 100.0 * r.reject_fraction << "%, bias z " << r.channels[0].bias_z
              << " " << r.channels[1].bias_z << " " << r.channels[2].bias_z << "\n";
    EXPECT_FALSE(r.passed);
    for (const ChannelReport& c : r.channels) {
      EXPECT_TRUE(c.bias_failed) << c.name;
      EXPECT_NEAR(c.mean_rel_diff, 0.03, 0.01) << c.name;
    }
    CompareOptions no_bias;
    no_bias.bias_alpha = 0.0;
    EXPECT_TRUE(compare_images(draw_image(biased, 7), draw_image(kReference, 8), no_bias).passed);
  }
  // 1024 spp: the per-pixel test alone rejects well above the 0.25% limit.
  {
    const Draw biased = draw(1024, 0.3f, 1.03f);
    const Draw ref = draw(4096, 0.3f);
    CompareOptions no_bias;
    no_bias.bias_alpha = 0.0;
    const CompareResult r = compare_images(draw_image(biased, 9), draw_image(ref, 10), no_bias);
    std::cout << "+3% at 1024 spp, per-pixel test only: rejecting share " << 100.0 * r.reject_fraction << "%\n";
    EXPECT_FALSE(r.passed);
    EXPECT_GT(r.reject_fraction, 0.005);
    const Draw unbiased = draw(1024, 0.3f);
    const CompareResult same = compare_images(draw_image(unbiased, 11), draw_image(ref, 10), no_bias);
    std::cout << "same distribution at 1024 spp: rejecting share " << 100.0 * same.reject_fraction << "%\n";
    EXPECT_TRUE(same.passed);
  }
}

TEST(ImageCompare, LocalThreePercentShiftFailsTheTileTest) {
  // +3% on one 16×16 tile at 64 spp: invisible per pixel and in the image mean, clear per tile.
  Draw patch = kTest;
  patch.scale = 1.03f;
  patch.patch = 16;
  const CompareResult r = compare_images(draw_image(patch, 61), draw_image(kReference, 62), {});
  std::cout << "+3% on a 16x16 patch at 64 spp: rejecting share " << 100.0 * r.reject_fraction << "%, tile z "
            << r.channels[0].tile_z << " " << r.channels[1].tile_z << " " << r.channels[2].tile_z << " (critical "
            << r.tile_z_critical << "), image bias z " << r.channels[0].bias_z << "\n";
  EXPECT_FALSE(r.passed);
  EXPECT_LT(r.reject_fraction, r.limit);
  int tiles_failed = 0;  // expected tile z ≈ 6.5 ± 1 per channel against a critical 4.26
  for (const ChannelReport& c : r.channels) {
    EXPECT_FALSE(c.bias_failed) << c.name;
    if (!c.tile_failed) continue;
    ++tiles_failed;
    EXPECT_EQ(c.tile_x, 16);
    EXPECT_EQ(c.tile_y, 16);
  }
  EXPECT_GE(tiles_failed, 2);
  CompareOptions no_tiles;
  no_tiles.bias_tile = 0;
  no_tiles.bias_grid = 0;
  EXPECT_TRUE(compare_images(draw_image(patch, 61), draw_image(kReference, 62), no_tiles).passed);
}

TEST(ImageCompare, OnePixelShiftFails) {
  Draw shifted = kTest;
  shifted.shift_x = 1;
  const CompareResult r = compare_images(draw_image(shifted, 21), draw_image(kReference, 22), {});
  std::cout << "1-pixel shift at 64 spp: rejecting share " << 100.0 * r.reject_fraction << "%\n";
  EXPECT_FALSE(r.passed);
  EXPECT_GT(r.reject_fraction, 0.1);  // block edges: a quarter of the columns
  EXPECT_GE(std::abs(r.worst.z), r.z_critical);
}

TEST(ImageCompare, CompanionVarianceAndSppScaling) {
  const Image ref_with_var = draw_image(kReference, 31);
  Image test = draw_image(draw(64, 0.5f, 1.0f, 0, false), 32);
  Image ref = make_image(kSize, kSize, {"R", "G", "B"});
  Image ref_var = make_image(kSize, kSize, {"R", "G", "B"});  // plain names in the companion
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < 3; ++c) {
        ref.at(x, y, c) = ref_with_var.at(x, y, c);
        ref_var.at(x, y, c) = ref_with_var.at(x, y, 3 + c);
      }
  ref.attributes = ref_with_var.attributes;
  // Only the reference's variance is known: the test's is estimated as var_ref · 4096/64.
  const CompareResult scaled = compare_images(test, ref, {}, nullptr, &ref_var);
  EXPECT_TRUE(scaled.passed) << format_compare_summary(scaled);
  EXPECT_NE(scaled.variance_model.find("spp"), std::string::npos);
  // Without spp headers the test is taken as exact and its own noise makes it fail.
  test.attributes.clear();
  const CompareResult exact = compare_images(test, ref, {}, nullptr, &ref_var);
  EXPECT_FALSE(exact.passed);
  EXPECT_GT(exact.reject_fraction, 0.1);
  // var.* names in a companion work too.
  Image var_named = ref_var;
  var_named.channels = {"var.R", "var.G", "var.B"};
  test.attributes = {{"sylva:spp", "64"}};
  EXPECT_TRUE(compare_images(test, ref, {}, nullptr, &var_named).passed);
}

TEST(ImageCompare, ZeroVarianceNeedsAMatch) {
  Image ref = make_image(8, 8, {"Y", "var.Y"});
  for (size_t p = 0; p < 64; ++p) ref.pixels[p * 2] = p % 3 == 0 ? 0.0f : 0.5f;
  Image test = ref;
  EXPECT_TRUE(compare_images(test, ref, {}).passed);
  test.pixels[2 * 5] = 0.5f * (1.0f + 1e-7f);  // float rounding passes
  EXPECT_TRUE(compare_images(test, ref, {}).passed);
  test.pixels[2 * 5] = 0.5005f;  // a real difference rejects
  const CompareResult r = compare_images(test, ref, {});
  EXPECT_EQ(r.rejected, 1);
  EXPECT_FALSE(r.passed);  // 1/64 > 0.25%
  EXPECT_EQ(r.worst.x, 5);
  EXPECT_EQ(r.worst.y, 0);
  test = ref;
  test.pixels[0] = std::nanf("");
  EXPECT_EQ(compare_images(test, ref, {}).rejected, 1);
  // Equal infinities (a miss's depth) match; different ones do not.
  test = ref;
  ref.pixels[2] = test.pixels[2] = std::numeric_limits<float>::infinity();
  ref.pixels[3] = test.pixels[3] = std::nanf("");  // its variance
  CompareOptions tol;
  tol.abs_tolerances = {{"Y", 0.001}};
  EXPECT_EQ(compare_images(test, ref, {}).rejected, 0);
  EXPECT_EQ(compare_images(test, ref, tol).rejected, 0);
  test.pixels[2] = -std::numeric_limits<float>::infinity();
  EXPECT_EQ(compare_images(test, ref, {}).rejected, 1);
  EXPECT_EQ(compare_images(test, ref, tol).rejected, 1);
}

TEST(ImageCompare, ExactAndToleranceChannels) {
  Image ref = make_image(10, 10, {"Z"});
  ref.add_channel("id.instance", PixelType::UInt);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) {
      ref.at(x, y, 0) = 10.0f + static_cast<float>(x);
      ref.at(x, y, 1) = static_cast<float>(y);
    }
  Image test = ref;
  test.at(3, 3, 0) += 0.0005f;
  CompareOptions options;
  options.abs_tolerances = {{"Z", 0.001}};
  options.max_reject_fraction = 0.0;
  CompareResult r = compare_images(test, ref, options);
  EXPECT_TRUE(r.passed) << format_compare_summary(r);
  ASSERT_EQ(r.channels.size(), 2u);
  EXPECT_EQ(r.channels[1].test, ChannelTest::Exact);  // UInt ⇒ exact
  test.at(3, 3, 0) += 0.001f;
  test.at(4, 4, 1) = 5.0f;
  r = compare_images(test, ref, options);
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.channels[0].rejected, 1);
  EXPECT_EQ(r.channels[1].rejected, 1);
  EXPECT_EQ(r.rejected, 2);
  // Without a tolerance Z has no variance: skipped by default, an error when asked for.
  EXPECT_EQ(compare_images(test, ref, {}).skipped, std::vector<std::string>{"Z"});
  CompareOptions ask;
  ask.channels = {"Z"};
  EXPECT_THROW(compare_images(test, ref, ask), Error);
  ask.exact_channels = {"Z"};
  EXPECT_EQ(compare_images(test, ref, ask).channels[0].test, ChannelTest::Exact);
  // An explicit tolerance overrides the exactness of an integer channel.
  CompareOptions id_tol;
  id_tol.channels = {"id.instance"};
  id_tol.abs_tolerances = {{"id.instance", 1.0}};
  const CompareResult loose = compare_images(test, ref, id_tol);
  EXPECT_EQ(loose.channels[0].test, ChannelTest::AbsTolerance);
  EXPECT_EQ(loose.rejected, 0);  // id 5 vs 4: |d| = 1 is not above 1
  id_tol.abs_tolerances = {{"id.instance", 0.5}};
  EXPECT_EQ(compare_images(test, ref, id_tol).rejected, 1);
}

TEST(ImageCompare, ThresholdFallbackMatchesIdiff) {
  Image ref = make_image(10, 10, {"R", "G", "B"});
  Image test = ref;
  test.at(1, 1, 0) = 0.3f;   // fails (> 0.25)
  test.at(1, 1, 2) = 0.5f;   // same pixel: still one failing pixel
  test.at(2, 2, 1) = -0.3f;  // fails
  test.at(3, 3, 1) = 0.25f;  // not above the threshold
  CompareOptions options;
  options.fail_threshold = 0.25;
  options.fail_percent = 1.0;
  CompareResult r = compare_images(test, ref, options);
  EXPECT_TRUE(r.threshold_mode);
  EXPECT_EQ(r.failing_pixels, 2);
  EXPECT_FALSE(r.passed);  // 2 > 1% of 100
  options.fail_percent = 2.0;
  EXPECT_TRUE(compare_images(test, ref, options).passed);  // 2 > 2 is false
}

TEST(ImageCompare, UnusableInputIsAnError) {
  const Image a = draw_image(kTest, 41);
  Image small = make_image(8, 8, {"R", "G", "B", "var.R", "var.G", "var.B"});
  EXPECT_THROW(compare_images(small, a, {}), Error);
  Image more = a;
  more.add_channel("nir.Y", PixelType::Float);
  try {
    compare_images(more, a, {});
    FAIL() << "expected sylva::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nir.Y"), std::string::npos) << e.what();
  }
  CompareOptions missing;
  missing.channels = {"albedo.R"};
  EXPECT_THROW(compare_images(a, a, missing), Error);
  const Image no_var = draw_image(draw(64, 0.5f, 1.0f, 0, false), 42);
  EXPECT_THROW(compare_images(no_var, no_var, {}), Error);  // nothing testable
  EXPECT_THROW(compare_images(a, a, {}, &small), Error);    // companion of the wrong size
}

TEST(CompareReport, WritesFilesAndListsFailuresFirst) {
  const fs::path dir = fs::temp_directory_path() / ("sylva_test_report_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  Image ref = draw_image(kReference, 51), test = draw_image(kTest, 52);
  // Add a nir band that is 10% too bright in the test: it must come first.
  for (Image* image : {&ref, &test}) {
    image->add_channel("nir.Y", PixelType::Float);
    image->add_channel("var.nir.Y", PixelType::Float);
  }
  const Image nir_ref = draw_image(kReference, 53), nir_test = draw_image(draw(64, 0.5f, 1.1f), 54);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      ref.at(x, y, 6) = nir_ref.at(x, y, 0);
      ref.at(x, y, 7) = nir_ref.at(x, y, 3);
      test.at(x, y, 6) = nir_test.at(x, y, 0);
      test.at(x, y, 7) = nir_test.at(x, y, 3);
    }
  const CompareResult r = compare_images(test, ref, {});
  ASSERT_FALSE(r.passed);
  ReportOptions options;
  options.test_label = "t.exr";
  write_compare_report(dir, test, ref, r, options);
  for (const char* f : {"test.exr", "ref.exr", "error.exr", "pvalue.exr", "index.html", "rgb_test.png", "rgb_ref.png",
                        "rgb_diff.png", "rgb_reject.png", "nir_Y_test.png", "nir_Y_diff.png", "nir_Y_reject.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const Image error = read_exr(dir / "error.exr");
  EXPECT_GE(error.find_channel("reject.Y"), 0);
  EXPECT_GE(error.find_channel("nir.Y"), 0);
  EXPECT_GE(read_exr(dir / "pvalue.exr").find_channel("R"), 0);

  std::stringstream html;
  html << std::ifstream(dir / "index.html").rdbuf();
  const std::string text = html.str();
  EXPECT_NE(text.find("id=\"verdict\">FAIL"), std::string::npos);
  const size_t table = text.find("id=\"channels\"");
  ASSERT_NE(table, std::string::npos);
  const size_t nir_row = text.find("<td>nir.Y</td>", table), r_row = text.find("<td>R</td>", table);
  ASSERT_NE(nir_row, std::string::npos);
  ASSERT_NE(r_row, std::string::npos);
  EXPECT_LT(nir_row, r_row);
  const size_t nir_item = text.find("id=\"item-nir_Y\""), rgb_item = text.find("id=\"item-rgb\"");
  ASSERT_NE(nir_item, std::string::npos);
  ASSERT_NE(rgb_item, std::string::npos);
  EXPECT_LT(nir_item, rgb_item);
  EXPECT_TRUE(test::atomic_temporaries_in(dir).empty());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sylva
