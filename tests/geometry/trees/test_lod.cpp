// The level-of-detail arithmetic of Weber & Penn §5 (geometry/trees/lod.h): the mass loop, the
// calibrated range and the level choice. The Quaking Aspen's Table 2 is in tests/scenes/test_lod.cpp.

#include "geometry/trees/lod.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace sylva {
namespace {

// §5's example: 160 cross-sections (10 masses of 16) with number 5.3 draw 6 in 3 masses and 5 in
// the other 7 (the paper: the first 3; here spread evenly, masses 3, 6 and 9).
TEST(LodLoop, PaperExample) {
  for (size_t m = 0; m < 10; ++m) EXPECT_EQ(lod_mass_drawn(m, 160, 5.3f, 16), m == 3 || m == 6 || m == 9 ? 6 : 5) << m;
  EXPECT_EQ(lod_drawn_count(160, 5.3f, 16), 53u);
  EXPECT_TRUE(lod_is_drawn(0, 160, 5.3f, 16));
  EXPECT_TRUE(lod_is_drawn(4, 160, 5.3f, 16));
  EXPECT_FALSE(lod_is_drawn(5, 160, 5.3f, 16));
  EXPECT_TRUE(lod_is_drawn(16 * 3 + 5, 160, 5.3f, 16));
  EXPECT_FALSE(lod_is_drawn(16 * 3 + 6, 160, 5.3f, 16));
}

// Half an element per mass (Table 2's leaf points at 1200 m) keeps one in every second mass, so
// both halves of a tree keep the same share.
TEST(LodLoop, FractionsSpreadEvenly) {
  const size_t total = 4 * 1000;
  size_t first_half = 0, second_half = 0;
  for (size_t i = 0; i < total; ++i)
    if (lod_is_drawn(i, total, 0.5f, 4)) ++(i < total / 2 ? first_half : second_half);
  EXPECT_EQ(first_half, 250u);
  EXPECT_EQ(second_half, 250u);
  for (size_t m = 0; m + 1 < 1000; m += 2)
    EXPECT_EQ(lod_mass_drawn(m, total, 0.5f, 4) + lod_mass_drawn(m + 1, total, 0.5f, 4), 1) << m;
}

TEST(LodLoop, CountsWithinOnePerMassAndMonotone) {
  for (const size_t total : {1u, 7u, 16u, 17u, 100u, 1000u}) {
    size_t previous = 0;
    for (int k = 0; k <= 64; ++k) {
      const float number = 16.0f * static_cast<float>(k) / 64.0f;
      const size_t drawn = lod_drawn_count(total, number, 16);
      // Each mass draws `number` of its 16 elements (a partial last mass its share), ± 1.
      const double expected = static_cast<double>(total) * number / 16.0;
      const double masses = std::ceil(static_cast<double>(total) / 16.0);
      EXPECT_LE(std::abs(static_cast<double>(drawn) - expected), masses) << total << " " << number;
      EXPECT_GE(drawn, previous);
      previous = drawn;
      size_t by_index = 0;
      for (size_t i = 0; i < total + 3; ++i) by_index += lod_is_drawn(i, total, number, 16) ? 1 : 0;
      EXPECT_EQ(by_index, drawn);
    }
    EXPECT_EQ(lod_drawn_count(total, 16.0f, 16), total);
    EXPECT_EQ(lod_drawn_count(total, 0.0f, 16), 0u);
  }
}

// The printed level-0 equation and the fits' limits.
TEST(LodNumbers, PrintedTrunkEquation) {
  EXPECT_FLOAT_EQ(lod_numbers(200).polygons[0], 16.0f);
  EXPECT_FLOAT_EQ(lod_numbers(600).polygons[0], 16.0f * (1.5f - 600.0f / 600.0f));
  EXPECT_FLOAT_EQ(lod_numbers(799).polygons[0], 16.0f * (1.5f - 799.0f / 600.0f));
  EXPECT_FLOAT_EQ(lod_numbers(801).polygons[0], 0.0f);
  EXPECT_FLOAT_EQ(lod_numbers(99).lines[0], 0.0f);
  EXPECT_FLOAT_EQ(lod_numbers(101).lines[0], 16.0f);
}

// Every number stays in [0, mass_size] and, with range, the drawn elements (finer or coarser
// primitive) never increase: detail falls monotonically.
TEST(LodNumbers, BoundedAndDrawnElementsFallWithRange) {
  LodNumbers previous = lod_numbers(0);
  for (int step = 1; step <= 3000; ++step) {
    const LodNumbers n = lod_numbers(static_cast<float>(step));
    for (size_t item = 0; item < 3; ++item) {
      EXPECT_GE(n.polygons[item], 0.0f);
      EXPECT_LE(n.polygons[item], 16.0f);
      EXPECT_LE(n.polygons[item], previous.polygons[item]) << step;
      EXPECT_LE(std::max(n.polygons[item], n.lines[item]), std::max(previous.polygons[item], previous.lines[item]));
    }
    EXPECT_FLOAT_EQ(std::max(n.polygons[0], n.lines[0]), 16.0f);  // the trunk never thins
    EXPECT_LE(n.leaf_polygons, previous.leaf_polygons);
    EXPECT_LE(std::max(n.leaf_polygons, n.leaf_points), std::max(previous.leaf_polygons, previous.leaf_points));
    EXPECT_GE(n.leaf_points, 0.5f);  // the floor read from Table 2's 600 and 1200 m cells
    previous = n;
  }
}

TEST(LodRange, CalibratedRangeIsThePapersForItsReferenceCamera) {
  // 1000 rows over 60°: r2 = range.
  const float footprint = 250.0f * 2.0f * std::tan(radians(30.0f)) / 1000.0f;
  EXPECT_NEAR(lod_calibrated_range(footprint), 250.0f, 1e-3f);
  // Half the rows: twice the footprint, twice r2 (the paper's 1000/height_image).
  EXPECT_NEAR(lod_calibrated_range(2.0f * footprint), 500.0f, 1e-3f);
}

TEST(LodLevel, ChoiceIsMonotoneAndCoversTheLevels) {
  int previous = 0;
  for (int k = 0; k <= 5000; ++k) {
    const int level = lod_level_for(static_cast<float>(k) * 0.5f);
    EXPECT_GE(level, previous);
    EXPECT_LT(level, static_cast<int>(kLodLevelR2.size()));
    previous = level;
  }
  EXPECT_EQ(previous, static_cast<int>(kLodLevelR2.size()) - 1);
  for (size_t k = 0; k < kLodLevelR2.size(); ++k) EXPECT_EQ(lod_level_for(kLodLevelR2[k]), static_cast<int>(k));
  EXPECT_EQ(lod_level_for(239.9f), 0);
  EXPECT_EQ(lod_level_for(std::numeric_limits<float>::quiet_NaN()), 0);
}

}  // namespace
}  // namespace sylva
