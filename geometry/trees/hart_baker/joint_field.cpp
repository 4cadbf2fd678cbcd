// A Hart–Baker joint plan's field: the tubes' own pieces, their union, blended at the joints
// (§5.2, docs/hart_baker.md "Blended joints").

#include "geometry/trees/hart_baker/surface_detail.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sylva {

namespace surface_detail {

namespace {

// The signed distance to a tube piece: across its axis to the round cone or, with `polygon`, to its
// polygon (corners rounded by rounding_m); along it to its ring planes (so that consecutive pieces meet
// exactly, as the tube's bands do at their shared ring).
float piece_distance(const Vec3& x, const TubePiece& p, bool polygon) {
  const Vec3 axis = p.cone.tip - p.cone.base;
  const float len2 = glm::dot(axis, axis);
  if (len2 <= 0) return std::numeric_limits<float>::infinity();
  const float t = glm::dot(x - p.cone.base, axis) / len2;
  const Vec3 q = x - (p.cone.base + axis * t);
  const float tc = std::clamp(t, 0.0f, 1.0f);
  const float r = (1 - tc) * p.cone.base_radius_m + tc * p.cone.tip_radius_m;
  float across = glm::length(q) - r;
  if (polygon && p.sides >= 3) {
    // The polygon moved in by ρ, rounded out by ρ: the distance to the inset flat facing x, or
    // beyond the end of that flat to its corner, less ρ.
    const float sector = 2 * kPi / static_cast<float>(p.sides);
    const float a = wrap(std::atan2(glm::dot(q, p.ey), glm::dot(q, p.ex)));
    const float mid = (std::floor(a / sector) + 0.5f) * sector;
    const float side = a < mid ? -1.0f : 1.0f;
    const Vec3 normal = std::cos(mid) * p.ex + std::sin(mid) * p.ey;
    const Vec3 along = side * (std::cos(mid) * p.ey - std::sin(mid) * p.ex);
    const float apothem = r * std::cos(0.5f * sector);
    const float rho = std::min(p.rounding_m, 0.5f * apothem);
    const float inset = apothem - rho, half_side = inset * std::tan(0.5f * sector);
    const float d = glm::dot(q, normal) - inset, beside = glm::dot(q, along);
    across = (beside > half_side && d > 0 ? glm::length(q - normal * inset - along * half_side) : d) - rho;
  }
  const float ends = std::max(glm::dot(p.cone.base - x, p.base_axis), glm::dot(x - p.cone.tip, p.tip_axis));
  return std::max(across, ends);
}

// Whether a piece, at least |x − centre| − radius from x, is certainly further than `bound`.
bool beyond(const Vec3& x, std::span<const PieceBall> balls, size_t i, float bound) {
  if (balls.empty()) return false;
  const float reach = bound + balls[i].radius;
  const Vec3 d = x - balls[i].centre;
  return reach < 0 || glm::dot(d, d) > reach * reach;
}

// The union of tube pieces: round, or as polygons. A polygon lies inside its circle by at most
// r (1 − cos(π/sides)) ≤ r (π/sides)²/2, so only pieces that close to the nearest round one are
// measured as polygons. `balls` (empty, or one per piece) skip the pieces certainly too far.
float pieces_union(const Vec3& x, std::span<const TubePiece> pieces, std::span<const PieceBall> balls, bool round) {
  if (round) {
    // For normals: the round cones with their round ends, whose gradient is radial across a ring
    // (a ring plane's own gradient, along the axis, would win within the polygon's sag of it).
    float least = std::numeric_limits<float>::infinity();
    for (size_t i = 0; i < pieces.size(); ++i) {
      if (beyond(x, balls, i, least)) continue;
      const ConeDistance cd = cone_distance(x, pieces[i].cone);
      least = std::min(least, cd.d - cd.r);
    }
    return least;
  }
  constexpr size_t kKept = 64;
  std::array<float, kKept> kept{};
  float bound = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < pieces.size(); ++i) {
    const TubePiece& p = pieces[i];
    const float f = beyond(x, balls, i, bound) ? std::numeric_limits<float>::infinity() : piece_distance(x, p, false);
    if (i < kKept) kept[i] = f;
    const float a = p.sides >= 3 ? kPi / static_cast<float>(p.sides) : 0.0f;
    bound = std::min(bound, f + std::max(p.cone.base_radius_m, p.cone.tip_radius_m) * 0.5f * a * a);
  }
  float f = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < pieces.size(); ++i) {
    const float r = i < kKept ? kept[i] : beyond(x, balls, i, bound) ? bound + 1 : piece_distance(x, pieces[i], false);
    if (r <= bound) f = std::min(f, piece_distance(x, pieces[i], true));
  }
  return f;
}

}  // namespace

std::vector<PieceBall> piece_balls(std::span<const TubePiece> pieces) {
  std::vector<PieceBall> balls;
  for (const TubePiece& p : pieces)
    balls.push_back({0.5f * (p.cone.base + p.cone.tip), 0.5f * glm::length(p.cone.tip - p.cone.base) +
                                                            std::max(p.cone.base_radius_m, p.cone.tip_radius_m)});
  return balls;
}

// The field of a joint plan: its joints' blends of its cones, the least (JointPlan).
float plan_field(const Vec3& x, std::span<const BlendCone> cones, std::span<const TubePiece> pieces,
                 std::span<const PieceBall> balls, std::span<const BlendJoint> joints, bool round) {
  float f = std::numeric_limits<float>::infinity();
  if (pieces.empty()) {
    for (const BlendJoint& j : joints) f = std::min(f, blended_cones(x, cones, j));
    return f;
  }
  const float f1 = pieces_union(x, pieces, balls, round);
  for (const BlendJoint& j : joints) f = std::min(f, blend_field(x, cones, f1, j));
  return f;
}

}  // namespace surface_detail

float joint_plan_field(const JointPlan& plan, const Vec3& x, bool round) {
  return surface_detail::plan_field(x, plan.cones, plan.pieces, {}, plan.joints, round);
}

}  // namespace sylva
