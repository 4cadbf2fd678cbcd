// Adaptive sampling and progressive passes (docs/sampling.md): the image is unbiased (z-tests over
// seeds against a uniform reference), each stream's count follows the rule, and the result is the
// same bits at any thread count, split by tiles, interrupted and resumed; sample splits and bad
// settings are refused; a time limit ends the render with samples over the whole image.

#include "core/error.h"
#include "render/session.h"
#include "tests/render/render_test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

namespace sylva {
namespace {

using test::same_bits;

// Sky above, lit ground and two leaf crowns: pixels whose noise differs by orders of magnitude.
RenderSettings adaptive_settings(int spp, float threshold) {
  RenderSettings s = test::test_settings(24, 16, spp, 16);
  s.noise_threshold = threshold;
  s.pilot_spp = 8;
  return s;
}

int channel(const Image& image, const char* name) {
  const int c = image.find_channel(name);
  EXPECT_GE(c, 0) << name;
  return c;
}

double image_mean(const Image& image, int c) {
  double sum = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) sum += image.at(x, y, c);
  return sum / (image.width * image.height);
}

TEST(Adaptive, CountsFollowTheRuleAndSpreadOverTheImage) {
  const Scene scene = test::small_forest_scene();
  Renderer renderer(scene, adaptive_settings(256, 0.1f));
  Film film = renderer.make_film();
  renderer.render(film);
  const Image image = renderer.make_image(film);
  const int spp = channel(image, "spp");
  int below = 0, above = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const auto n = static_cast<uint32_t>(image.at(x, y, spp));
      EXPECT_EQ(n, film.count(x, y));
      EXPECT_GE(n, 8u);
      EXPECT_LE(n, 256u);
      below += n < 32;
      above += n > 128;
    }
  // The lit ground converges early; the crowns' edges and shadows ask for more.
  std::vector<uint32_t> counts;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) counts.push_back(film.count(x, y));
  std::sort(counts.begin(), counts.end());
  const std::string spread = "counts from " + std::to_string(counts.front()) + " (median " +
                             std::to_string(counts[counts.size() / 2]) + ") to " + std::to_string(counts.back());
  EXPECT_GT(below, 0) << spread;
  EXPECT_GT(above, 0) << spread;
}

// The mean over many seeds of adaptive renders equals a uniform reference: over the whole image and
// over the pixels that stopped below the most samples (where a rule that looked at a pixel's own
// samples would bias it).
TEST(Adaptive, UnbiasedAgainstUniformSampling) {
  const Scene scene = test::small_forest_scene();
  RenderSettings ref_settings = adaptive_settings(2048, 0.0f);
  ref_settings.seed = 99;
  Renderer reference(scene, ref_settings);
  Film ref_film = reference.make_film();
  reference.render(ref_film);
  const Image ref = reference.make_image(ref_film);
  constexpr int kSeeds = 24;
  for (const char* name : {"R", "G", "nir.Y"}) {
    const int c = channel(ref, name), var_c = channel(ref, (std::string("var.") + name).c_str());
    std::vector<double> whole, early;
    // Pixels that stop early in the first seed's render, held fixed over the seeds.
    std::vector<bool> stops_early;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      RenderSettings settings = adaptive_settings(128, 0.1f);
      settings.seed = static_cast<uint64_t>(seed);
      Renderer renderer(scene, settings);
      Film film = renderer.make_film();
      renderer.render(film);
      const Image image = renderer.make_image(film);
      if (stops_early.empty())
        for (int y = 0; y < image.height; ++y)
          for (int x = 0; x < image.width; ++x) stops_early.push_back(film.count(x, y) > 8 && film.count(x, y) < 128);
      whole.push_back(image_mean(image, c));
      double sum = 0;
      size_t n = 0, i = 0;
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x, ++i)
          if (stops_early[i]) sum += image.at(x, y, c), ++n;
      ASSERT_GT(n, 10u);
      early.push_back(sum / static_cast<double>(n));
    }
    const auto z_test = [&](const std::vector<double>& values, bool early_only) {
      double mean = 0, ref_mean = 0, ref_var = 0;
      for (const double v : values) mean += v / kSeeds;
      double var = 0;
      for (const double v : values) var += sqr(v - mean) / (kSeeds - 1);
      size_t n = 0, i = 0;
      for (int y = 0; y < ref.height; ++y)
        for (int x = 0; x < ref.width; ++x, ++i)
          if (!early_only || stops_early[i]) ref_mean += ref.at(x, y, c), ref_var += ref.at(x, y, var_c), ++n;
      ref_mean /= static_cast<double>(n);
      ref_var /= sqr(static_cast<double>(n));
      return (mean - ref_mean) / std::sqrt(var / kSeeds + ref_var);
    };
    EXPECT_LT(std::abs(z_test(whole, false)), 4.0) << name << ": the whole image";
    EXPECT_LT(std::abs(z_test(early, true)), 4.0) << name << ": the pixels that stop early";
  }
}

TEST(Adaptive, SameBitsAtAnyThreadCountSplitByTilesAndResumed) {
  const Scene scene = test::small_forest_scene();
  const EmbreeScene embree(scene);
  RenderSettings settings = adaptive_settings(64, 0.05f);
  settings.features = true;  // the denoiser's half-buffers are the streams
  settings.threads = 1;
  Renderer one(scene, embree, settings);
  Film expected = one.make_film();
  one.render(expected);
  const std::string expected_bytes = test::film_bytes(expected);
  settings.threads = 2;
  Renderer two(scene, embree, settings);
  Film film = two.make_film();
  two.render(film);
  EXPECT_EQ(test::film_bytes(film), expected_bytes) << "2 threads";
  EXPECT_TRUE(same_bits(one.make_image(expected), two.make_image(film)));
  // Two tiles, rendered into films of their own and merged.
  Film merged = two.make_film();
  for (const PixelRegion& r : {PixelRegion{0, 0, 24, 7}, PixelRegion{0, 7, 24, 16}}) {
    Film part = two.make_film(r, 0);
    two.render(part);
    merged.merge(part);
  }
  EXPECT_EQ(test::film_bytes(merged), expected_bytes) << "tiles";
  // Interrupted after a while, then resumed.
  std::atomic<bool> cancel{false};
  settings.cancel = &cancel;
  Renderer stoppable(scene, embree, settings);
  Film resumed = stoppable.make_film();
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    cancel = true;
  });
  const RenderStats first = stoppable.render(resumed);
  stopper.join();
  cancel = false;
  stoppable.render(resumed);
  EXPECT_EQ(test::film_bytes(resumed), expected_bytes)
      << "resumed (first part interrupted: " << first.interrupted << ")";
  // Sample splits are refused.
  Film chunk = two.make_film(two.image_region(), 16);
  EXPECT_THROW(two.render(chunk, two.image_region(), SampleRange{16, 64}), Error);
}

TEST(Adaptive, BadSettingsAreRefused) {
  const Scene scene = test::small_forest_scene();
  RenderSettings s = adaptive_settings(64, 0.05f);
  s.noise_channels = {"Q"};
  EXPECT_THROW(Renderer renderer(scene, s), Error);
  s.noise_channels = {"R", "nir.Y"};
  EXPECT_NO_THROW(Renderer renderer(scene, s));
  s.pilot_spp = 7;
  EXPECT_THROW(Renderer renderer(scene, s), Error);
  s.pilot_spp = 128;  // more than spp
  EXPECT_THROW(Renderer renderer(scene, s), Error);
  s.pilot_spp = 8;
  s.noise_threshold = 1.5f;
  EXPECT_THROW(Renderer renderer(scene, s), Error);
}

TEST(Progressive, SameBitsAsOnePass) {
  const Scene scene = test::small_forest_scene();
  const EmbreeScene embree(scene);
  RenderSettings settings = test::test_settings(24, 16, 40, 16);
  Renderer one_pass(scene, embree, settings);
  Film expected = one_pass.make_film();
  one_pass.render(expected);
  settings.progressive = true;
  Renderer passes(scene, embree, settings);
  Film film = passes.make_film();
  passes.render(film);
  EXPECT_EQ(test::film_bytes(film), test::film_bytes(expected));
}

TEST(Progressive, TimeLimitEndsWithSamplesEverywhere) {
  const Scene scene = test::small_forest_scene();
  const EmbreeScene embree(scene);
  RenderSettings settings = test::test_settings(24, 16, 1 << 20, 16);
  settings.time_limit_s = 0.5;
  RenderSession session(scene, embree, settings, SessionOptions{});
  const SessionResult result = session.run();
  EXPECT_TRUE(result.time_limited);
  EXPECT_FALSE(result.interrupted);
  uint32_t least = UINT32_MAX, most = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) {
      least = std::min(least, result.film.count(x, y));
      most = std::max(most, result.film.count(x, y));
    }
  // Passes of 8, 16, 32 … samples: the pass in progress is at most one level above the last.
  EXPECT_GE(least, 8u);
  EXPECT_LE(most, 2 * least);
  EXPECT_LT(most, 1u << 20);
}

}  // namespace
}  // namespace sylva
