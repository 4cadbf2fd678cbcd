// Leaf outlines (geometry/leaf_shape.h): Weber & Penn §4.5 shapes as alpha masks.

#include "core/math.h"
#include "geometry/leaf_shape.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

constexpr LeafShape kShapes[] = {LeafShape::Oval,   LeafShape::Triangle, LeafShape::Oak3,
                                 LeafShape::Maple3, LeafShape::Maple5,   LeafShape::Leaflets3};

TEST(LeafShape, NamesRoundTrip) {
  for (int s = 0; s < static_cast<int>(LeafShape::Count); ++s) {
    const auto shape = static_cast<LeafShape>(s);
    EXPECT_EQ(leaf_shape_from_name(leaf_shape_name(shape)), shape);
  }
  EXPECT_FALSE(leaf_shape_from_name("fern").has_value());
}

TEST(LeafShape, OutlinesAreSymmetricAboutTheMidribAndInsideTheQuad) {
  for (const LeafShape shape : kShapes) {
    EXPECT_TRUE(leaf_shape_inside(shape, 0.5f, 0.3f)) << leaf_shape_name(shape);  // on the midrib
    EXPECT_FALSE(leaf_shape_inside(shape, 0.02f, 0.98f)) << leaf_shape_name(shape);
    EXPECT_FALSE(leaf_shape_inside(shape, 0.98f, 0.98f)) << leaf_shape_name(shape);
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 32; ++i) {
        const float u = (i + 0.5f) / 64.0f, v = (j + 0.5f) / 64.0f;
        ASSERT_EQ(leaf_shape_inside(shape, u, v), leaf_shape_inside(shape, 1.0f - u, v)) << leaf_shape_name(shape);
      }
    // Only the triangle's base reaches the petiole-end corners.
    EXPECT_EQ(leaf_shape_inside(shape, 0.001f, 0.001f), shape == LeafShape::Triangle) << leaf_shape_name(shape);
  }
}

TEST(LeafShape, Coverage) {
  EXPECT_NEAR(leaf_shape_coverage(LeafShape::Rectangle), 1.0f, 1e-6f);
  EXPECT_NEAR(leaf_shape_coverage(LeafShape::Oval), kPi / 4.0f, 2e-3f);
  EXPECT_NEAR(leaf_shape_coverage(LeafShape::Triangle), 0.5f, 2e-3f);
  EXPECT_NEAR(leaf_shape_coverage(LeafShape::RightTriangle), 0.5f, 5e-3f);
  for (const LeafShape shape : {LeafShape::Oak3, LeafShape::Maple3, LeafShape::Maple5, LeafShape::Leaflets3}) {
    EXPECT_GT(leaf_shape_coverage(shape), 0.2f) << leaf_shape_name(shape);
    EXPECT_LT(leaf_shape_coverage(shape), 0.7f) << leaf_shape_name(shape);
  }
}

TEST(LeafShape, RightTriangleHasItsRightAngleAtThePetioleCorner) {
  EXPECT_TRUE(leaf_shape_inside(LeafShape::RightTriangle, 0.001f, 0.001f));
  EXPECT_TRUE(leaf_shape_inside(LeafShape::RightTriangle, 0.98f, 0.01f));
  EXPECT_TRUE(leaf_shape_inside(LeafShape::RightTriangle, 0.01f, 0.98f));
  EXPECT_FALSE(leaf_shape_inside(LeafShape::RightTriangle, 0.6f, 0.6f));
  EXPECT_FALSE(leaf_shape_inside(LeafShape::RightTriangle, 0.98f, 0.98f));
}

TEST(LeafShape, LobesAndSinuses) {
  // Oak3: two rounded lateral lobes with a sinus between them and the terminal lobe.
  EXPECT_TRUE(leaf_shape_inside(LeafShape::Oak3, 0.5f + 0.4f, 0.6f));
  EXPECT_FALSE(leaf_shape_inside(LeafShape::Oak3, 0.5f + 0.3f, 0.85f));
  EXPECT_TRUE(leaf_shape_inside(LeafShape::Oak3, 0.5f, 0.97f));
  // Maple3: pointed terminal lobe, notches beside it, side lobes.
  EXPECT_TRUE(leaf_shape_inside(LeafShape::Maple3, 0.5f, 0.93f));
  EXPECT_FALSE(leaf_shape_inside(LeafShape::Maple3, 0.5f + 0.25f, 0.75f));
  EXPECT_TRUE(leaf_shape_inside(LeafShape::Maple3, 0.5f + 0.4f, 0.58f));
  // Maple5: five tips (terminal, two upper, two lower).
  EXPECT_TRUE(leaf_shape_inside(LeafShape::Maple5, 0.5f, 0.95f));
  EXPECT_TRUE(leaf_shape_inside(LeafShape::Maple5, 0.805f, 0.716f));
  EXPECT_TRUE(leaf_shape_inside(LeafShape::Maple5, 0.5f + 0.36f, 0.4f));
  EXPECT_FALSE(leaf_shape_inside(LeafShape::Maple5, 0.5f + 0.28f, 0.82f));
  // Leaflets3: a stalk, gaps between the leaflets.
  EXPECT_TRUE(leaf_shape_inside(LeafShape::Leaflets3, 0.5f, 0.1f));
  EXPECT_FALSE(leaf_shape_inside(LeafShape::Leaflets3, 0.45f, 0.1f));
  EXPECT_TRUE(leaf_shape_inside(LeafShape::Leaflets3, 0.5f + 0.22f, 0.4f));
  EXPECT_FALSE(leaf_shape_inside(LeafShape::Leaflets3, 0.5f + 0.2f, 0.75f));
}

}  // namespace
}  // namespace sylva
