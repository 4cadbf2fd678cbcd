#include "geometry/trees/weber_penn/weber_penn_shape.h"

#include <cmath>

namespace sylva::wp {

float shape_ratio(int shape, float ratio, const Envelope& envelope, Reading reading) {
  // Weber & Penn §4.3, the ShapeRatio table; shape 8 from §4.6.
  switch (shape) {
    case 0:
      return reading == Reading::Arbaro ? ratio : 0.2f + 0.8f * ratio;
    case 1:
      return 0.2f + 0.8f * std::sin(kPi * ratio);
    case 2:
      return 0.2f + 0.8f * std::sin(0.5f * kPi * ratio);
    case 3:
      return 1.0f;
    case 4:
      return 0.5f + 0.5f * ratio;
    case 5:
      return ratio <= 0.7f ? ratio / 0.7f : (1.0f - ratio) / 0.3f;
    case 6:
      return 1.0f - 0.8f * ratio;
    case 7:
      return ratio <= 0.7f ? 0.5f + 0.5f * ratio / 0.7f : 0.5f + 0.5f * (1.0f - ratio) / 0.3f;
    case 8: {
      if (ratio < 0.0f || ratio > 1.0f) return 0.0f;
      const float peak = envelope.width_peak;
      if (ratio < 1.0f - peak) return std::pow(ratio / (1.0f - peak), envelope.power_high);
      // Continuous at the peak (docs/design.md §5.1): (1 − ratio)/P, not the printed (1 − ratio)/(1 − P).
      if (peak <= 0.0f) return 1.0f;
      return std::pow((1.0f - ratio) / peak, envelope.power_low);
    }
    default:
      return 1.0f;
  }
}

float taper_radius(float taper, float radius_stem, float length_stem, float z) {
  // Weber & Penn §4.4, radius_Z.
  float unit_taper = 0.0f;
  if (taper < 1.0f)
    unit_taper = taper;
  else if (taper < 2.0f)
    unit_taper = 2.0f - taper;
  const float taper_z = radius_stem * (1.0f - unit_taper * z);
  if (taper < 1.0f) return taper_z;
  const float z2 = (1.0f - z) * length_stem;
  const float depth = (taper < 2.0f || z2 < taper_z) ? 1.0f : taper - 2.0f;
  float z3 = z2;
  if (taper >= 2.0f && taper_z > 0.0f) z3 = std::abs(z2 - 2.0f * taper_z * std::floor(z2 / (2.0f * taper_z) + 0.5f));
  if (taper < 2.0f && z3 >= taper_z) return taper_z;
  return (1.0f - depth) * taper_z + depth * safe_sqrt(sqr(taper_z) - sqr(z3 - taper_z));
}

float flare_scale(float flare, float z) {
  // Weber & Penn §4.4, flare_Z; y limited to a minimum of zero.
  const float y = std::max(0.0f, 1.0f - 8.0f * z);
  return flare * (std::pow(100.0f, y) - 1.0f) / 100.0f + 1.0f;
}

float lobe_scale(int lobes, float lobe_depth, float angle_rad) {
  return 1.0f + lobe_depth * std::sin(static_cast<float>(lobes) * angle_rad);
}

bool inside_envelope(const Vec3& p, float scale_tree, float base_size, const Envelope& envelope) {
  // Weber & Penn §4.6, 'inside', with the horizontal distance (docs/design.md §5.1).
  const float r = std::sqrt(p.x * p.x + p.y * p.y);
  const float ratio = (scale_tree - p.z) / (scale_tree * (1.0f - base_size));
  return r / scale_tree < envelope.width * shape_ratio(8, ratio, envelope);
}

int diffuse_splits(float seg_splits, float& error) {
  // Weber & Penn §4.2, Floyd–Steinberg style error diffusion per stem level.
  const float effective = seg_splits + error;
  const int splits = static_cast<int>(std::lround(effective));
  error -= static_cast<float>(splits) - seg_splits;
  return std::max(0, splits);
}

float split_angle_deg(float split_angle, float split_angle_v, float u, float declination_deg) {
  return std::max(0.0f, split_angle + split_angle_v * u - declination_deg);
}

float split_spread_deg(float declination_deg, float u) {
  return 20.0f + 0.75f * (30.0f + std::abs(declination_deg - 90.0f)) * u * u;
}

float segment_curve_deg(float curve, float curve_back, int curve_res, int segment) {
  const float n = static_cast<float>(std::max(1, curve_res));
  if (curve_back == 0.0f) return curve / n;
  return segment < (curve_res + 1) / 2 ? 2.0f * curve / n : 2.0f * curve_back / n;
}

float attraction_up_rad(float attraction_up, float frame_z_z, int curve_res) {
  // Weber & Penn §4.8, turned about the horizontal (docs/weber_penn.md).
  const float declination = safe_acos(frame_z_z);
  return attraction_up * std::abs(declination * std::sin(declination)) / static_cast<float>(std::max(1, curve_res));
}

float down_angle_deg(float down_angle, float down_angle_v, float position_ratio, float u, Reading reading) {
  if (down_angle_v >= 0.0f) return down_angle + down_angle_v * u;
  return down_angle + down_angle_v * (1.0f - 2.0f * shape_ratio(0, position_ratio, {}, reading));
}

float rotate_angle_deg(float rotate, float rotate_v, float previous_deg, int alternate, float u) {
  if (rotate >= 0.0f) return previous_deg + rotate + rotate_v * u;
  return static_cast<float>(alternate) * (180.0f + rotate + rotate_v * u);
}

float child_length_level1(int shape, const Envelope& envelope, float length_trunk, float length_base,
                          float length_child_max, float offset, Reading reading) {
  const float span = length_trunk - length_base;
  const float ratio = span > 0.0f ? (length_trunk - offset) / span : 1.0f;
  return length_trunk * length_child_max * shape_ratio(shape, ratio, envelope, reading);
}

float child_length_deeper(float length_child_max, float length_parent, float offset) {
  return length_child_max * (length_parent - 0.6f * offset);
}

float child_count_level1(int branches, float length, float length_parent, float length_child_max) {
  if (length_parent <= 0.0f || length_child_max <= 0.0f) return 0.0f;
  return static_cast<float>(branches) * (0.2f + 0.8f * (length / length_parent) / length_child_max);
}

float child_count_deeper(int branches, float offset, float length_parent) {
  if (length_parent <= 0.0f) return 0.0f;
  return static_cast<float>(branches) * (1.0f - 0.5f * offset / length_parent);
}

float leaf_count(int leaves, int distrib, float offset, float length_parent, float quality, Reading reading) {
  const float ratio = length_parent > 0.0f ? offset / length_parent : 1.0f;
  return static_cast<float>(leaves) * shape_ratio(distrib, ratio, {}, reading) * quality;
}

float child_radius(float radius_parent, float length_child, float length_parent, float ratio_power) {
  if (length_parent <= 0.0f) return radius_parent;
  return radius_parent * std::pow(length_child / length_parent, ratio_power);
}

Sway sway_angles(float length_stem, float radius_stem, float radius_z, float z, int curve_res, float wind_speed,
                 float wind_gust, float time_s, float time_scale, float sway_offset_x, float sway_offset_y) {
  // Weber & Penn §4.7 with the equations of issue 3.
  if (length_stem <= 0.0f || radius_z <= 0.0f) return {};
  const float a0 = 4.0f * length_stem * (1.0f - z) / radius_z;
  const float a1 = wind_speed / 50.0f * a0;
  const float a2 = wind_gust / 50.0f * a0 + a1 / 2.0f;
  const float phase = radius_stem / length_stem * time_s / 15.0f * time_scale;
  const float bx = sway_offset_x + phase;
  const float by = sway_offset_y + phase;
  const float n = static_cast<float>(std::max(1, curve_res));
  return {(a1 * std::sin(bx) + a2 * std::sin(0.7f * bx)) / n, (a1 * std::sin(by) + a2 * std::sin(0.7f * by)) / n};
}

}  // namespace sylva::wp
