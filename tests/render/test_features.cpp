// The denoiser's features (RenderSettings::features): they leave every other channel's bits as
// they are, the half-buffers split the beauty, the class fractions and the sky's albedo are what
// docs/denoise.md says, and sample chunks with features merge bit-identically to one render.

#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {
namespace features_test {

using test::film_bytes;
using test::stand_scene;
using test::test_settings;

constexpr int kWidth = 36, kHeight = 20, kSpp = 10, kDepth = 6;

RenderSettings settings(bool features) {
  RenderSettings s = test_settings(kWidth, kHeight, kSpp, kDepth);
  s.features = features;
  return s;
}

Image render(const Scene& scene, const EmbreeScene& embree, bool features, int threads = 0) {
  RenderSettings s = settings(features);
  s.threads = threads;
  Renderer r(scene, embree, s);
  Film film = r.make_film();
  r.render(film);
  return r.make_image(film);
}

TEST(Features, LeaveEveryOtherChannelAsItIs) {
  const Scene scene = stand_scene();
  const EmbreeScene embree(scene);
  const Image off = render(scene, embree, false), on = render(scene, embree, true);
  ASSERT_GT(on.channel_count(), off.channel_count());
  for (int c = 0; c < off.channel_count(); ++c) {
    ASSERT_EQ(on.channels[c], off.channels[c]);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) ASSERT_EQ(on.at(x, y, c), off.at(x, y, c)) << off.channels[c];
  }
  EXPECT_TRUE(test::same_bits(on, render(scene, embree, true, 1)));  // any thread count
}

TEST(Features, HalvesSplitTheBeautyAndClassesSumToOne) {
  const Scene scene = stand_scene();
  const EmbreeScene embree(scene);
  const Image im = render(scene, embree, true);
  int sky_pixels = 0, leaf_pixels = 0, ground_pixels = 0;
  for (const std::string c : {"R", "G", "B", "nir.Y"}) {
    const int mean = im.find_channel(c), even = im.find_channel("even." + c), odd = im.find_channel("odd." + c);
    ASSERT_GE(even, 0) << c;
    ASSERT_GE(odd, 0) << c;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)  // kSpp even: the halves have 5 samples each
        EXPECT_NEAR(0.5 * (im.at(x, y, even) + im.at(x, y, odd)), im.at(x, y, mean), 1e-5 * (1 + im.at(x, y, mean)));
  }
  const int sky = im.find_channel("feature.class.sky"), sun = im.find_channel("feature.sun");
  const int albedo = im.find_channel("albedo.R"), feature_albedo = im.find_channel("feature.albedo.R");
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      double total = 0;
      for (const char* k : {"leaf", "bark", "ground", "sky"})
        total += im.at(x, y, im.find_channel(std::string("feature.class.") + k));
      EXPECT_NEAR(total, 1.0, 1e-6);
      EXPECT_NEAR(im.at(x, y, feature_albedo), im.at(x, y, albedo) + im.at(x, y, sky), 2e-3);
      const float s = im.at(x, y, sun);
      EXPECT_TRUE(s >= 0.0f && s <= 1.0f);
      sky_pixels += im.at(x, y, sky) == 1.0f;
      leaf_pixels += im.at(x, y, im.find_channel("feature.class.leaf")) > 0.5f;
      ground_pixels += im.at(x, y, im.find_channel("feature.class.ground")) > 0.5f;
      if (im.at(x, y, sky) == 1.0f) {
        EXPECT_EQ(im.at(x, y, feature_albedo), 1.0f);  // safe to divide by
      }
    }
  EXPECT_GT(sky_pixels, 0);
  EXPECT_GT(leaf_pixels, 0);
  EXPECT_GT(ground_pixels, 0);
}

TEST(Features, ShadowFeatureSeesBothSunAndShadeOnTheGround) {
  const Scene scene = stand_scene();
  const EmbreeScene embree(scene);
  const Image im = render(scene, embree, true);
  const int ground = im.find_channel("feature.class.ground"), sun = im.find_channel("feature.sun");
  int lit = 0, shaded = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      if (im.at(x, y, ground) == 1.0f) {
        lit += im.at(x, y, sun) == 1.0f;
        shaded += im.at(x, y, sun) < 0.5f;  // mostly in a shadow (the leaf clouds are sparse)
      }
  EXPECT_GT(lit, 0);
  EXPECT_GT(shaded, 0);
}

TEST(Features, SampleChunksMergeBitIdenticalToOneRender) {
  const Scene scene = stand_scene();
  const EmbreeScene embree(scene);
  Renderer r(scene, embree, settings(true));
  Film whole = r.make_film();
  r.render(whole);
  for (int n : {2, 3}) {
    Film merged;
    for (int i = 0; i < n; ++i) {
      const SampleRange range = sample_chunk({0, kSpp}, i, n);
      Film chunk = r.make_film(r.image_region(), range.first);
      r.render(chunk, r.image_region(), range);
      if (i == 0)
        merged = std::move(chunk);
      else
        merged.merge(chunk);
    }
    EXPECT_EQ(film_bytes(merged), film_bytes(whole)) << n;
  }
}

}  // namespace features_test
}  // namespace
}  // namespace sylva
