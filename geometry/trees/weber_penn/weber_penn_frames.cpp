#include "geometry/trees/weber_penn/weber_penn_frames.h"

#include <algorithm>
#include <cmath>

namespace sylva::wp {
namespace {

// Rodrigues rotation of v about the unit axis k by the angle whose cosine and sine are c and s.
Vec3 rotate_vector(const Vec3& v, const Vec3& k, float c, float s) {
  return v * c + glm::cross(k, v) * s + k * (glm::dot(k, v) * (1.0f - c));
}

}  // namespace

// Rotations of a frame about its own axes, right-handed, angles in radians.
Frame rotate_x(const Frame& f, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return Frame{f.x, c * f.y + s * f.z, c * f.z - s * f.y};
}
Frame rotate_y(const Frame& f, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return Frame{c * f.x - s * f.z, f.y, c * f.z + s * f.x};
}
Frame rotate_z(const Frame& f, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return Frame{c * f.x + s * f.y, c * f.y - s * f.x, f.z};
}
Frame rotate_axis(const Frame& f, const Vec3& k, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return Frame{rotate_vector(f.x, k, c, s), rotate_vector(f.y, k, c, s), rotate_vector(f.z, k, c, s)};
}
// Rotation of a frame about the tree's vertical axis.
Frame rotate_about_vertical(const Frame& f, float a) {
  const float c = std::cos(a), s = std::sin(a);
  auto r = [&](const Vec3& v) { return Vec3(c * v.x - s * v.y, s * v.x + c * v.y, v.z); };
  return Frame{r(f.x), r(f.y), r(f.z)};
}

// §4.3 orientation of a child stem or leaf: turn about the parent's axis by nRotate (alternating
// when negative; `rotate_deg` and `alternate` carry the running state along the parent) or, for a
// fan, by `fan_deg` about the parent's y axis; then tilt down by nDownAngle at `ratio` along it.
Frame orient_child(const Frame& parent_frame, const WeberPennLevel& lp, Reading reading, float ratio, float u_down,
                   float u_rot, bool fan, float fan_deg, float& rotate_deg, int& alternate) {
  const float down = down_angle_deg(lp.down_angle, lp.down_angle_v, ratio, u_down, reading);
  if (fan) return rotate_x(rotate_y(parent_frame, radians(fan_deg)), radians(down));
  rotate_deg = rotate_angle_deg(lp.rotate, lp.rotate_v, rotate_deg, alternate, u_rot);
  if (lp.rotate < 0.0f) alternate = -alternate;
  return rotate_x(rotate_z(parent_frame, radians(rotate_deg)), radians(down));
}
Frame orthonormalized(const Frame& f) {
  const Vec3 z = glm::normalize(f.z);
  Vec3 x = f.x - z * glm::dot(f.x, z);
  const float lx = glm::length(x);
  if (lx < 1e-6f) return Frame::from_z(z);
  x /= lx;
  return Frame{x, glm::cross(z, x), z};
}

// Turns frame f so that its z axis becomes `to` (unit), by the shortest rotation.
Frame turn_to(const Frame& f, const Vec3& to) {
  const Vec3 axis = glm::cross(f.z, to);
  const float s = glm::length(axis);
  if (s < 1e-7f) return f;
  return orthonormalized(rotate_axis(f, axis / s, std::atan2(s, glm::dot(f.z, to))));
}

// §4.8: turns f up by `angle_rad` (down when negative) about the horizontal axis across its z axis.
Frame turn_up(const Frame& f, float angle_rad) {
  const Vec3 across{-f.z.y, f.z.x, 0.0f};
  const float l = glm::length(across);
  if (l < 1e-6f) return f;
  return rotate_axis(f, across / l, -angle_rad);
}

// A stem on flat ground: a segment of length `seg_len` from `start` whose end would come closer to
// the ground than `clearance` (its radius there) is turned up, keeping its heading, just enough to
// stay at that height; the stem then goes on from the turned frame, as if grown along the ground.
Frame keep_above_ground(const Frame& f, const Vec3& start, float seg_len, float clearance) {
  if (seg_len <= 0.0f) return f;
  const float need = (clearance - start.z) / seg_len;  // the least z component of the direction
  if (f.z.z >= need) return f;
  const float up = std::min(need, 1.0f);
  Vec3 heading{f.z.x, f.z.y, 0.0f};
  const float h = glm::length(heading);
  heading = h > 1e-6f ? heading / h : Vec3(1.0f, 0.0f, 0.0f);
  return turn_to(f, heading * std::sqrt(std::max(0.0f, 1.0f - up * up)) + Vec3(0.0f, 0.0f, up));
}

}  // namespace sylva::wp
