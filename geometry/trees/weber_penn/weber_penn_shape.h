#pragma once
// The closed-form pieces of the Weber & Penn (1995) tree model, as pure functions so each one can
// be tested against hand-computed values. Angles are in degrees where the paper uses degrees (the
// function names say so); lengths in metres. Sylva's readings of the paper's ambiguous places are
// those of docs/design.md §5.1.

#include "core/math.h"

#include <cstdint>

namespace sylva::wp {

// The two readings of the paper's ambiguous places (docs/weber_penn.md, "Readings"): Paper follows
// the paper's text where the plates agree with it; Arbaro follows Arbaro's code (the reference
// open implementation), so that an Arbaro species file looks in Sylva as it does in Arbaro.
enum class Reading { Paper, Arbaro };

// The pruning envelope (§4.6): PruneWidth, PruneWidthPeak, PrunePowerLow, PrunePowerHigh.
struct Envelope {
  float width = 0.5f;
  float width_peak = 0.5f;
  float power_low = 0.5f;
  float power_high = 0.5f;
};

// Weber & Penn §4.3, ShapeRatio(shape, ratio) for the nine shapes 0..8. Shape 0 (conical) is
// 0.2 + 0.8·ratio as printed (Reading::Paper) or the plain ratio (Reading::Arbaro). Shape 8 is the envelope of §4.6;
// below the peak (ratio ≥ 1 − P) it uses (1 − ratio)/P instead of the printed (1 − ratio)/(1 − P) so that it is
// continuous at the peak (docs/design.md §5.1); it is 0 outside [0, 1]. Other shape ids behave like 3 (cylindrical).
float shape_ratio(int shape, float ratio, const Envelope& envelope = {}, Reading reading = Reading::Paper);

// Weber & Penn §4.4, radius_Z: the tapered radius at unit position z ∈ [0, 1] of a stem with base
// radius `radius_stem` and length `length_stem`, for nTaper in [0, 3) (0 cylinder, 1 cone,
// 2 spherical end, (2, 3) periodic tapering).
float taper_radius(float taper, float radius_stem, float length_stem, float z);

// Weber & Penn §4.4, flare_Z: the trunk's radius scale near the ground, ≥ 1 and ≤ 1 + Flare.
float flare_scale(float flare, float z);

// Weber & Penn §4.4, lobe_Z = 1 + LobeDepth·sin(Lobes·angle), angle about the stem from its x axis.
float lobe_scale(int lobes, float lobe_depth, float angle_rad);

// Weber & Penn §4.6, 'inside': whether tree-space point p (metres, trunk base at the origin, before
// ZScale) lies in the pruning envelope of a tree of height scale_tree whose bare base is BaseSize.
// Uses the horizontal distance sqrt(x² + y²) (docs/design.md §5.1).
bool inside_envelope(const Vec3& p, float scale_tree, float base_size, const Envelope& envelope);

// Weber & Penn §4.2: error-diffused integer split count. Adds the running `error` of the stem
// level to `seg_splits`, rounds to the nearest integer and keeps the rounding error.
int diffuse_splits(float seg_splits, float& error);

// Weber & Penn §4.2: angle_split = max(0, (nSplitAngle ± nSplitAngleV) − declination), u ∈ [−1, 1).
float split_angle_deg(float split_angle, float split_angle_v, float u, float declination_deg);

// Weber & Penn §4.2: the spread of a single clone about the tree's vertical axis,
// 20 + 0.75·(30 + |declination − 90|)·u², u ∈ [0, 1). The caller applies a random sign.
float split_spread_deg(float declination_deg, float u);

// Weber & Penn §4.1: the curvature of segment `segment` of `curve_res` (without the random part).
// nCurveBack = 0: nCurve/nCurveRes each; otherwise 2·nCurve/nCurveRes over the first half and
// 2·nCurveBack/nCurveRes over the second half (docs/design.md §5.1: the total bend is nCurve).
float segment_curve_deg(float curve, float curve_back, int curve_res, int segment);

// Weber & Penn §4.8, curve_up_segment in radians from the z component of the segment's direction:
// AttractionUp·|declination·sin(declination)|/nCurveRes (docs/weber_penn.md: the turn is about the
// horizontal axis perpendicular to the stem, so the paper's cos(orientation) factor, the part of a
// turn about the stem's x axis that changes the declination, is 1; the sin keeps an upright or a
// hanging stem where it is instead of swinging it past the vertical). Positive values turn the
// stem upward.
float attraction_up_rad(float attraction_up, float frame_z_z, int curve_res);

// Weber & Penn §4.3, down angle of a child. nDownAngleV ≥ 0: nDownAngle ± nDownAngleV (u ∈ [−1, 1)).
// nDownAngleV < 0: nDownAngle + nDownAngleV·(1 − 2·ShapeRatio(0, ratio)), no random term, where
// ratio = (length_parent − offset)/(length_parent − length_base) (docs/design.md §5.1).
float down_angle_deg(float down_angle, float down_angle_v, float position_ratio, float u,
                     Reading reading = Reading::Paper);

// Weber & Penn §4.3, rotate angle of a child about its parent's z axis in degrees. nRotate ≥ 0:
// previous + nRotate ± nRotateV. nRotate < 0: alternating sides, ±(180 + nRotate ± nRotateV) from
// the parent's y axis; `alternate` is +1 or −1 and flips on every child.
float rotate_angle_deg(float rotate, float rotate_v, float previous_deg, int alternate, float u);

// Weber & Penn §4.3, child lengths. Level 1 (children of the trunk):
// length_trunk·length_child_max·ShapeRatio(Shape, (length_trunk − offset)/(length_trunk − length_base)).
float child_length_level1(int shape, const Envelope& envelope, float length_trunk, float length_base,
                          float length_child_max, float offset, Reading reading = Reading::Paper);
// Deeper levels: length_child_max·(length_parent − 0.6·offset).
float child_length_deeper(float length_child_max, float length_parent, float offset);

// Weber & Penn §4.3, number of children of a level-1 stem:
// nBranches·(0.2 + 0.8·(length/length_parent)/length_child_max).
float child_count_level1(int branches, float length, float length_parent, float length_child_max);
// Number of children of a stem at level ≥ 2: nBranches·(1 − 0.5·offset/length_parent).
float child_count_deeper(int branches, float offset, float length_parent);

// Weber & Penn §4.5, leaves on a last-level stem: Leaves·ShapeRatio(distrib, offset/length_parent)
// ·quality (distrib = 4, tapered cylindrical, in the paper; Arbaro's LeafDistrib may change it).
float leaf_count(int leaves, int distrib, float offset, float length_parent, float quality,
                 Reading reading = Reading::Paper);

// Weber & Penn §4.4: radius_child = radius_parent·(length_child/length_parent)^RatioPower.
float child_radius(float radius_parent, float length_child, float length_parent, float ratio_power);

// Weber & Penn §4.7, wind sway with the equations of issue 3 (the seed text lost them):
//   a0 = 4·L·(1 − Z)/r_Z, a1 = speed/50·a0, a2 = gust/50·a0 + a1/2,
//   b = sway_offset + r_stem/L·t/15·time_scale,
//   sway = (a1·sin(b) + a2·sin(0.7·b))/nCurveRes   (degrees).
// time_scale = 1 is the literal reading; Sylva's default 180/π follows Blender's Sapling.
struct Sway {
  float x_deg = 0;
  float y_deg = 0;
};
Sway sway_angles(float length_stem, float radius_stem, float radius_z, float z, int curve_res, float wind_speed,
                 float wind_gust, float time_s, float time_scale, float sway_offset_x, float sway_offset_y);

}  // namespace sylva::wp
