// Local tests of an image comparison (compare/regions.h): Holm's procedure on known p-values, the
// regions made from id channels, and on synthetic labelled Monte Carlo images (a sky, a ground,
// small "trees" of one class): a shift confined to the trees or to one tree fails there and only
// there, too much scatter in the sky fails the variance test, and independent draws fail at most
// at the family's α.

#include "compare/image_compare.h"
#include "compare/regions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

namespace sylva {
namespace regions_test {
namespace {

constexpr int kSize = 96;

// Which label a pixel has: sky (top third), ground, or one of nine small round trees (class 2,
// objects 11..19, radius 5 px, about 8 % of the image) standing on the ground.
struct Labels {
  int instance = 0, object = 0, klass = 0;
};

Labels labels_at(int x, int y) {
  for (int k = 0; k < 9; ++k) {
    const int cx = 10 + 10 * k + (k % 2) * 2, cy = 40 + (k % 3) * 17;
    if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= 25) return {2 + k, 11 + k, 2};
  }
  if (y < kSize / 3) return {0, 0, 0};
  return {1, 1, 1};
}

struct LabelledDraw {
  int spp = 64;
  double tree_scale = 1.0;  // multiplies μ of every tree
  int object = 0;           // > 0: object_scale applies to this object only
  double object_scale = 1.0;
  double sky_sigma_scale = 1.0;  // the sky's actual σ, times what var.* says
};

// R,G,B with var.*, id.instance, id.object, id.class; pixel means Gaussian around μ with per-sample
// σ = 0.5 μ, estimated variance σ²/spp · χ²(spp−1)/(spp−1).
Image labelled_image(const LabelledDraw& d, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::gamma_distribution<double> chi2_half((d.spp - 1) / 2.0, 2.0);
  Image image = make_image(kSize, kSize, {"R", "G", "B", "var.R", "var.G", "var.B"});
  for (const char* id : {"id.instance", "id.object", "id.class"}) image.add_channel(id, PixelType::UInt);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const Labels l = labels_at(x, y);
      for (int c = 0; c < 3; ++c) {
        double mu = l.klass == 0 ? 0.6 + 0.1 * c : l.klass == 1 ? 0.3 : 0.15 + 0.1 * (c == 1);
        if (l.klass == 2) mu *= d.tree_scale;
        if (l.object == d.object) mu *= d.object_scale;
        const double var_mean = std::pow(0.5 * mu, 2) / d.spp;
        const double actual_sigma = std::sqrt(var_mean) * (l.klass == 0 ? d.sky_sigma_scale : 1.0);
        image.at(x, y, c) = static_cast<float>(mu + normal(rng) * actual_sigma);
        image.at(x, y, 3 + c) = static_cast<float>(var_mean * chi2_half(rng) / (d.spp - 1));
      }
      image.at(x, y, 6) = static_cast<float>(l.instance);
      image.at(x, y, 7) = static_cast<float>(l.object);
      image.at(x, y, 8) = static_cast<float>(l.klass);
    }
  image.attributes = {{"sylva:spp", std::to_string(d.spp)}};
  return image;
}

const Image& reference() {
  static const Image ref = labelled_image(LabelledDraw{.spp = 4096}, 1);
  return ref;
}

const RegionTest* find_region(const CompareResult& r, const std::string& channel, RegionKind kind, int64_t label) {
  for (const RegionTest& t : r.regions)
    if (t.channel == channel && t.kind == kind && t.label == label) return &t;
  return nullptr;
}

TEST(Holm, StepDownOnKnownPValues) {
  // m = 4 at α = 0.05: thresholds 0.0125, 0.0167, 0.025, 0.05.
  std::vector<RegionTest> tests(4);
  const double p[] = {0.01, 0.04, 0.015, 0.3};
  for (size_t i = 0; i < 4; ++i) tests[i].bias_p = p[i];
  EXPECT_EQ(holm(tests, 0.05), 4);
  EXPECT_TRUE(tests[0].bias_failed);   // 0.01 ≤ 0.0125
  EXPECT_TRUE(tests[2].bias_failed);   // 0.015 ≤ 0.0167
  EXPECT_FALSE(tests[1].bias_failed);  // 0.04 > 0.025: stops here
  EXPECT_FALSE(tests[3].bias_failed);
  EXPECT_NEAR(tests[0].bias_p_holm, 0.04, 1e-12);
  EXPECT_NEAR(tests[2].bias_p_holm, 0.045, 1e-12);
  EXPECT_NEAR(tests[1].bias_p_holm, 0.08, 1e-12);
  EXPECT_NEAR(tests[3].bias_p_holm, 0.3, 1e-12);
  // The step-down stops at the first acceptance even if a later p is below its own threshold.
  std::vector<RegionTest> two(2);
  two[0].bias_p = 0.03;
  two[1].bias_p = 0.04;
  two[1].variance_tested = true;
  two[1].variance_p = 0.5;
  EXPECT_EQ(holm(two, 0.05), 3);
  EXPECT_FALSE(two[0].bias_failed);  // 0.03 > 0.05/3
  EXPECT_FALSE(two[1].bias_failed);
}

TEST(Regions, MadeFromTheReferenceIds) {
  RegionOptions options;
  const RegionMaps maps = make_region_maps(reference(), options);
  EXPECT_EQ(maps.tile, 16);
  EXPECT_EQ(maps.grid_cell, 0);  // 24-pixel cells: less than two tiles
  std::vector<RegionKind> kinds;
  for (const RegionMaps::Partition& p : maps.partitions) kinds.push_back(p.kind);
  EXPECT_EQ(kinds, (std::vector<RegionKind>{RegionKind::Image, RegionKind::Tile, RegionKind::Class, RegionKind::Object,
                                            RegionKind::Sky}));
  const RegionMaps::Partition& objects = maps.partitions[3];
  // The ground (object 1) and the nine trees of 81 pixels each: all above 64 pixels.
  EXPECT_EQ(objects.labels.size(), 10u);
  EXPECT_EQ(objects.pixels[1], 81);
  EXPECT_EQ(objects.boxes[1], (std::array<int, 4>{5, 35, 16, 46}));
  options.min_pixels = 100;
  EXPECT_EQ(make_region_maps(reference(), options).partitions[3].labels.size(), 1u);  // the ground only
  options.grid = 2;                                                                   // 48-pixel cells
  EXPECT_EQ(make_region_maps(reference(), options).grid_cell, 48);
}

TEST(Regions, AShiftOnTheTreesFailsTheirClassOnly) {
  // +2 % on 8 % of the pixels: about z 0.3 per pixel, 1.4 over the image, 2.9 over one tree, 8.6
  // over the class.
  const CompareResult r = compare_images(labelled_image({.tree_scale = 1.02}, 2), reference(), {});
  std::cout << format_compare_summary(r);
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.rejected, 0);
  int class_failures = 0;
  for (const RegionTest& t : r.regions) {
    if (t.kind == RegionKind::Class && t.label == 2 && t.bias_failed) {
      ++class_failures;
      EXPECT_GT(t.bias_z, 0.0);
      EXPECT_NEAR(t.mean_shift, 0.02, 0.01);
    }
    if (t.failed()) {
      const bool tree = (t.kind == RegionKind::Class && t.label == 2) || (t.kind == RegionKind::Object && t.label > 10);
      EXPECT_TRUE(tree) << region_name(t) << " " << t.channel;
    }
  }
  EXPECT_GE(class_failures, 2);
  CompareOptions no_labels;
  no_labels.label_regions = false;
  EXPECT_TRUE(compare_images(labelled_image({.tree_scale = 1.02}, 2), reference(), no_labels).passed);
}

TEST(Regions, AShiftOnOneTreeFailsThatObject) {
  const CompareResult r = compare_images(labelled_image({.object = 15, .object_scale = 1.08}, 3), reference(), {});
  EXPECT_FALSE(r.passed);
  int failures = 0;
  for (const char* c : {"R", "G", "B"}) {
    const RegionTest* t = find_region(r, c, RegionKind::Object, 15);
    ASSERT_NE(t, nullptr);
    failures += t->bias_failed ? 1 : 0;
    EXPECT_EQ(t->pixels, 81);
  }
  EXPECT_GE(failures, 2);
  for (const RegionTest& t : r.regions)
    if (t.failed() && t.kind != RegionKind::Tile && t.kind != RegionKind::Class) {
      EXPECT_EQ(t.label, 15) << region_name(t);
    }
  EXPECT_NE(format_compare_summary(r).find("object 15"), std::string::npos);
}

TEST(Regions, TooMuchScatterInTheSkyFailsTheVarianceTest) {
  // The sky's pixel means scatter 1.3 times as far as var.* says (σ² × 1.69): no bias anywhere.
  const CompareResult r = compare_images(labelled_image({.sky_sigma_scale = 1.3}, 4), reference(), {});
  EXPECT_FALSE(r.passed);
  for (const char* c : {"R", "G", "B"}) {
    const RegionTest* sky = find_region(r, c, RegionKind::Sky, 0);
    ASSERT_NE(sky, nullptr);
    EXPECT_TRUE(sky->variance_failed) << c << " scatter " << sky->variance_ratio << " z " << sky->variance_z;
    EXPECT_NEAR(sky->variance_ratio, 1.69, 0.25);
    EXPECT_FALSE(sky->bias_failed);
  }
  CompareOptions no_variance;
  no_variance.variance_test = false;
  EXPECT_TRUE(compare_images(labelled_image({.sky_sigma_scale = 1.3}, 4), reference(), no_variance).passed);
}

TEST(Regions, IndependentDrawsFailAtMostAtTheFamilysAlpha) {
  // 200 comparisons of independent draws at bias_alpha 0.05 (the family: image, tiles, classes,
  // objects, sky, bias and variance, 3 channels): Holm holds the false-alarm rate at ≤ 5 %.
  // Binomial(200, 0.05) exceeds 20 with probability 0.16 %.
  CompareOptions options;
  options.bias_alpha = 0.05;
  int failures = 0;
  int64_t family = 0;
  for (int t = 0; t < 200; ++t) {
    const Image ref = labelled_image({.spp = 1024}, 5000 + t);
    const CompareResult r = compare_images(labelled_image({}, 9000 + t), ref, options);
    failures += r.passed ? 0 : 1;
    family = r.family_size;
  }
  std::cout << "independent draws at family alpha 0.05 (" << family << " tests): " << failures << " of 200 fail\n";
  EXPECT_LE(failures, 20);
}

}  // namespace
}  // namespace regions_test
}  // namespace sylva
