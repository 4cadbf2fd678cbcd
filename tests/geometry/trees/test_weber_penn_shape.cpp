// Weber & Penn formulas (geometry/trees/weber_penn/weber_penn_shape.h) against hand-computed values.

#include "geometry/trees/weber_penn/weber_penn_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace sylva::wp {
namespace {

constexpr float kTol = 1e-5f;

TEST(WeberPennShape, ShapeRatioTableAllNineShapes) {
  // §4.3 table at ratio 0.25 and 0.8 (both branches of the piecewise shapes).
  EXPECT_NEAR(shape_ratio(0, 0.25f), 0.4f, kTol);        // 0.2 + 0.8·0.25
  EXPECT_NEAR(shape_ratio(1, 0.25f), 0.7656854f, kTol);  // 0.2 + 0.8·sin(π/4)
  EXPECT_NEAR(shape_ratio(2, 0.25f), 0.5061467f, kTol);  // 0.2 + 0.8·sin(π/8)
  EXPECT_NEAR(shape_ratio(3, 0.25f), 1.0f, kTol);
  EXPECT_NEAR(shape_ratio(4, 0.25f), 0.625f, kTol);        // 0.5 + 0.5·0.25
  EXPECT_NEAR(shape_ratio(5, 0.25f), 0.25f / 0.7f, kTol);  // ratio/0.7
  EXPECT_NEAR(shape_ratio(5, 0.8f), 0.2f / 0.3f, kTol);    // (1 − ratio)/0.3
  EXPECT_NEAR(shape_ratio(6, 0.25f), 0.8f, kTol);          // 1 − 0.8·0.25
  EXPECT_NEAR(shape_ratio(7, 0.25f), 0.5f + 0.5f * 0.25f / 0.7f, kTol);
  EXPECT_NEAR(shape_ratio(7, 0.8f), 0.5f + 0.5f * 0.2f / 0.3f, kTol);
  const Envelope e{0.5f, 0.6f, 1.0f, 0.5f};                     // width, peak P, power low, power high
  EXPECT_NEAR(shape_ratio(8, 0.2f, e), std::sqrt(0.5f), kTol);  // (0.2/(1 − P))^high
  EXPECT_NEAR(shape_ratio(8, 0.7f, e), 0.5f, kTol);             // ((1 − 0.7)/P)^low
  EXPECT_NEAR(shape_ratio(8, 0.4f, e), 1.0f, kTol);             // the peak
  EXPECT_NEAR(shape_ratio(8, 0.4f - 1e-4f, e), 1.0f, 1e-3f);    // continuous at the peak
  EXPECT_EQ(shape_ratio(8, -0.1f, e), 0.0f);
  EXPECT_EQ(shape_ratio(8, 1.1f, e), 0.0f);
}

TEST(WeberPennShape, TaperAllModes) {
  // §4.4 radius_Z; radius 0.5 m, length 10 m unless noted.
  EXPECT_NEAR(taper_radius(0.0f, 0.5f, 10.0f, 0.5f), 0.5f, kTol);    // cylinder
  EXPECT_NEAR(taper_radius(0.5f, 0.5f, 10.0f, 0.5f), 0.375f, kTol);  // r(1 − 0.5·0.5)
  EXPECT_NEAR(taper_radius(1.0f, 0.5f, 10.0f, 0.5f), 0.25f, kTol);   // cone
  EXPECT_NEAR(taper_radius(1.0f, 0.5f, 10.0f, 1.0f), 0.0f, kTol);
  EXPECT_NEAR(taper_radius(1.5f, 0.5f, 10.0f, 0.5f), 0.375f, kTol);  // unit_taper 0.5
  // nTaper 1.5, L = 1: at Z = 0.9, taper_Z = 0.275, Z2 = 0.1 < taper_Z: sqrt(0.275² − 0.175²).
  EXPECT_NEAR(taper_radius(1.5f, 0.5f, 1.0f, 0.9f), std::sqrt(0.045f), kTol);
  // nTaper 2: cylinder ending in a hemisphere of the stem's radius.
  EXPECT_NEAR(taper_radius(2.0f, 0.5f, 10.0f, 0.5f), 0.5f, kTol);
  EXPECT_NEAR(taper_radius(2.0f, 0.5f, 10.0f, 0.98f), 0.4f, kTol);  // Z2 = 0.2: sqrt(0.25 − 0.09)
  EXPECT_NEAR(taper_radius(2.0f, 0.5f, 10.0f, 1.0f), 0.0f, kTol);
  // nTaper 2.5: periodic, depth 0.5. Z2 = 5 is a sphere boundary (Z3 = 0), Z2 = 5.5 a sphere centre.
  EXPECT_NEAR(taper_radius(2.5f, 0.5f, 10.0f, 0.5f), 0.25f, kTol);
  EXPECT_NEAR(taper_radius(2.5f, 0.5f, 10.0f, 0.45f), 0.5f, kTol);
}

TEST(WeberPennShape, Flare) {
  EXPECT_NEAR(flare_scale(1.0f, 0.0f), 1.99f, kTol);          // Flare·(100¹ − 1)/100 + 1
  EXPECT_NEAR(flare_scale(1.0f, 1.0f / 16.0f), 1.09f, kTol);  // y = 0.5: (10 − 1)/100 + 1
  EXPECT_NEAR(flare_scale(0.6f, 0.125f), 1.0f, kTol);         // y limited to 0
  EXPECT_NEAR(flare_scale(0.6f, 0.7f), 1.0f, kTol);
}

TEST(WeberPennShape, Lobes) {
  EXPECT_NEAR(lobe_scale(5, 0.1f, kPi / 10.0f), 1.1f, kTol);  // sin(5·π/10) = 1
  EXPECT_NEAR(lobe_scale(5, 0.1f, 3.0f * kPi / 10.0f), 0.9f, kTol);
  EXPECT_NEAR(lobe_scale(5, 0.1f, 0.0f), 1.0f, kTol);
  EXPECT_NEAR(lobe_scale(5, 0.0f, 1.0f), 1.0f, kTol);
}

TEST(WeberPennShape, EnvelopeInsideOutside) {
  // Scale 10, BaseSize 0.2, PruneWidth 0.5, peak 0.5, linear powers. At z = 5: ratio = 5/8,
  // ShapeRatio(8) = (1 − 0.625)/0.5 = 0.75, so the envelope's radius is 0.5·0.75·10 = 3.75 m.
  const Envelope e{0.5f, 0.5f, 1.0f, 1.0f};
  EXPECT_TRUE(inside_envelope({3.7f, 0.0f, 5.0f}, 10.0f, 0.2f, e));
  EXPECT_TRUE(inside_envelope({2.6f, 2.6f, 5.0f}, 10.0f, 0.2f, e));  // horizontal distance 3.68
  EXPECT_FALSE(inside_envelope({3.8f, 0.0f, 5.0f}, 10.0f, 0.2f, e));
  // Above the peak, z = 8: ratio 0.25, ShapeRatio(8) = 0.25/0.5, radius 2.5 m.
  EXPECT_TRUE(inside_envelope({0.0f, 2.4f, 8.0f}, 10.0f, 0.2f, e));
  EXPECT_FALSE(inside_envelope({0.0f, 2.6f, 8.0f}, 10.0f, 0.2f, e));
  EXPECT_FALSE(inside_envelope({0.1f, 0.0f, 10.5f}, 10.0f, 0.2f, e));  // above the top
  EXPECT_FALSE(inside_envelope({0.1f, 0.0f, 1.0f}, 10.0f, 0.2f, e));   // below BaseSize
}

TEST(WeberPennShape, ErrorDiffusedSplitsAverageSegSplits) {
  for (const float seg_splits : {0.2f, 0.5f, 1.2f, 0.37f}) {
    float error = 0.0f;
    int total = 0, consecutive_extra = 0, max_consecutive_extra = 0;
    const int base = static_cast<int>(std::floor(seg_splits));
    for (int i = 0; i < 1000; ++i) {
      const int n = diffuse_splits(seg_splits, error);
      EXPECT_TRUE(n == base || n == base + 1) << n;
      total += n;
      consecutive_extra = n > base ? consecutive_extra + 1 : 0;
      max_consecutive_extra = std::max(max_consecutive_extra, consecutive_extra);
    }
    EXPECT_NEAR(total / 1000.0, seg_splits, 1.5e-3) << seg_splits;
    if (seg_splits - static_cast<float>(base) < 0.5f) {
      EXPECT_EQ(max_consecutive_extra, 1) << seg_splits;
    }
  }
  // 0.2: one split every fifth segment, evenly (§4.2).
  float error = 0.0f;
  std::string pattern;
  for (int i = 0; i < 10; ++i) pattern += static_cast<char>('0' + diffuse_splits(0.2f, error));
  EXPECT_EQ(pattern, "0010000100");
}

TEST(WeberPennShape, SplitAngles) {
  EXPECT_NEAR(split_angle_deg(30.0f, 10.0f, 0.5f, 12.0f), 23.0f, kTol);  // (30 + 5) − 12
  EXPECT_NEAR(split_angle_deg(30.0f, 10.0f, 0.5f, 50.0f), 0.0f, kTol);   // limited to 0
  EXPECT_NEAR(split_spread_deg(90.0f, 0.0f), 20.0f, kTol);
  EXPECT_NEAR(split_spread_deg(90.0f, 1.0f - 1e-7f), 42.5f, 1e-4f);  // 20 + 0.75·30
  EXPECT_NEAR(split_spread_deg(0.0f, 1.0f - 1e-7f), 110.0f, 1e-4f);  // 20 + 0.75·120
  EXPECT_NEAR(split_spread_deg(0.0f, 0.5f), 42.5f, kTol);            // 20 + 0.75·120·0.25
}

TEST(WeberPennShape, SegmentCurveSumsToCurve) {
  EXPECT_NEAR(segment_curve_deg(40.0f, 0.0f, 5, 0), 8.0f, kTol);
  float total = 0.0f;
  for (int i = 0; i < 10; ++i) total += segment_curve_deg(-40.0f, 0.0f, 10, i);
  EXPECT_NEAR(total, -40.0f, 1e-4f);
  // CurveBack: the first half turns by nCurve, the second by nCurveBack.
  float first = 0.0f, second = 0.0f;
  for (int i = 0; i < 8; ++i) (i < 4 ? first : second) += segment_curve_deg(40.0f, 80.0f, 8, i);
  EXPECT_NEAR(first, 40.0f, 1e-4f);
  EXPECT_NEAR(second, 80.0f, 1e-4f);
}

TEST(WeberPennShape, AttractionUp) {
  // AttractionUp·|declination·sin(declination)|/nCurveRes, from the z component of the direction.
  EXPECT_NEAR(attraction_up_rad(1.0f, 0.0f, 1), kPi / 2.0f, kTol);  // horizontal: declination π/2
  EXPECT_NEAR(attraction_up_rad(0.5f, 0.0f, 5), kPi / 20.0f, kTol);
  EXPECT_NEAR(attraction_up_rad(-3.0f, 0.0f, 3), -kPi / 2.0f, kTol);
  EXPECT_NEAR(attraction_up_rad(1.0f, std::cos(kPi / 4.0f), 1), kPi / 4.0f * std::sin(kPi / 4.0f), kTol);
  EXPECT_NEAR(attraction_up_rad(1.0f, 1.0f, 1), 0.0f, kTol);     // upright: stays
  EXPECT_NEAR(attraction_up_rad(-3.0f, -1.0f, 1), 0.0f, 1e-5f);  // hanging: stays, no swing past it
}

TEST(WeberPennShape, ConicalShapeByReading) {
  EXPECT_NEAR(shape_ratio(0, 0.25f, {}, Reading::Paper), 0.4f, kTol);  // 0.2 + 0.8·ratio as printed
  EXPECT_NEAR(shape_ratio(0, 0.25f, {}, Reading::Arbaro), 0.25f, kTol);
  // Negative nDownAngleV uses ShapeRatio(0): the aspen's top branches (60, −50) at 30° or 10°.
  EXPECT_NEAR(down_angle_deg(60.0f, -50.0f, 0.0f, 0.0f, Reading::Paper), 30.0f, kTol);
  EXPECT_NEAR(down_angle_deg(60.0f, -50.0f, 0.0f, 0.0f, Reading::Arbaro), 10.0f, kTol);
  Envelope e;
  EXPECT_NEAR(child_length_level1(0, e, 10.0f, 2.0f, 0.3f, 5.0f, Reading::Arbaro), 10.0f * 0.3f * 0.625f, kTol);
  EXPECT_NEAR(leaf_count(10, 0, 2.0f, 4.0f, 1.0f, Reading::Arbaro), 5.0f, kTol);
}

TEST(WeberPennShape, DownAngles) {
  EXPECT_NEAR(down_angle_deg(60.0f, 10.0f, 0.3f, 0.5f), 65.0f, kTol);  // nDownAngle ± V
  // Negative V: by position along the parent (Black Tupelo, 1DownAngle 60, 1DownAngleV −40).
  EXPECT_NEAR(down_angle_deg(60.0f, -40.0f, 1.0f, 0.9f), 100.0f, kTol);  // base: 60 − 40·(1 − 2)
  EXPECT_NEAR(down_angle_deg(60.0f, -40.0f, 0.0f, 0.9f), 36.0f, kTol);   // top: 60 − 40·(1 − 0.4)
  EXPECT_NEAR(down_angle_deg(60.0f, -40.0f, 0.5f, -0.9f), 60.0f + 40.0f * 0.2f, kTol);
}

TEST(WeberPennShape, RotateAngles) {
  EXPECT_NEAR(rotate_angle_deg(140.0f, 0.0f, 100.0f, 1, 0.3f), 240.0f, kTol);
  EXPECT_NEAR(rotate_angle_deg(140.0f, 20.0f, 0.0f, 1, -0.5f), 130.0f, kTol);
  EXPECT_NEAR(rotate_angle_deg(-120.0f, 30.0f, 999.0f, 1, 0.5f), 75.0f, kTol);  // 180 − 120 + 15
  EXPECT_NEAR(rotate_angle_deg(-120.0f, 30.0f, 999.0f, -1, 0.5f), -75.0f, kTol);
}

TEST(WeberPennShape, ChildLengthsCountsRadii) {
  const Envelope e;
  // Level 1: length_trunk·length_child_max·ShapeRatio(Shape, (L − offset)/(L − L_base)).
  EXPECT_NEAR(child_length_level1(3, e, 10.0f, 2.0f, 0.3f, 5.0f), 3.0f, kTol);
  EXPECT_NEAR(child_length_level1(0, e, 10.0f, 2.0f, 0.3f, 5.0f), 10.0f * 0.3f * 0.7f, kTol);  // ratio 0.625
  EXPECT_NEAR(child_length_deeper(0.5f, 4.0f, 1.0f), 1.7f, kTol);                              // 0.5·(4 − 0.6)
  EXPECT_NEAR(child_count_level1(30, 3.0f, 10.0f, 0.3f), 30.0f, kTol);
  EXPECT_NEAR(child_count_level1(30, 1.5f, 10.0f, 0.3f), 30.0f * 0.6f, kTol);
  EXPECT_NEAR(child_count_deeper(10, 2.0f, 4.0f), 7.5f, kTol);
  EXPECT_NEAR(leaf_count(25, 4, 2.0f, 4.0f, 1.0f), 18.75f, kTol);  // 25·(0.5 + 0.5·0.5)
  EXPECT_NEAR(leaf_count(25, 4, 2.0f, 4.0f, 0.5f), 9.375f, kTol);
  EXPECT_NEAR(child_radius(0.2f, 2.0f, 8.0f, 1.2f), 0.2f * std::pow(0.25f, 1.2f), kTol);
}

TEST(WeberPennShape, WindSway) {
  // a0 = 4·10·0.5/0.1 = 200, a1 = 5/50·200 = 20, a2 = 0 + 10.
  const Sway s = sway_angles(10.0f, 0.2f, 0.1f, 0.5f, 5, 5.0f, 0.0f, 0.0f, 1.0f, kPi / 2.0f, 0.0f);
  EXPECT_NEAR(s.x_deg, (20.0f + 10.0f * std::sin(0.7f * kPi / 2.0f)) / 5.0f, 1e-4f);
  EXPECT_NEAR(s.y_deg, 0.0f, 1e-4f);
  // The phase advances by r_stem/L·t/15·time_scale: 0.02·15/15·1 = 0.02 rad with the literal scale.
  const Sway t = sway_angles(10.0f, 0.2f, 0.1f, 0.5f, 5, 5.0f, 0.0f, 15.0f, 1.0f, 0.0f, 0.0f);
  EXPECT_NEAR(t.x_deg, (20.0f * std::sin(0.02f) + 10.0f * std::sin(0.014f)) / 5.0f, 1e-4f);
  const Sway u = sway_angles(10.0f, 0.2f, 0.1f, 0.5f, 5, 0.0f, 0.0f, 15.0f, 1.0f, 1.0f, 1.0f);
  EXPECT_EQ(u.x_deg, 0.0f);  // no wind, no sway
}

}  // namespace
}  // namespace sylva::wp
