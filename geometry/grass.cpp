#include "geometry/grass.h"

#include "core/error.h"
#include "core/rng.h"

#include <array>
#include <cmath>

namespace sylva {

CurveSet make_grass_patch(const GrassParams& params, uint64_t seed) {
  const double blades = static_cast<double>(params.density_per_m2) * sqr(static_cast<double>(params.patch_size_m));
  if (!(blades >= 0.0) || blades > 5e7) throw Error("a grass patch must have between 0 and 5e7 blades");
  const auto count = static_cast<size_t>(std::llround(blades));
  CurveSet c;
  c.points.reserve(4 * count);
  c.normals.reserve(4 * count);
  for (size_t i = 0; i < count; ++i) {
    Pcg32 rng(hash_ids(seed, i));
    const Vec2 u = uniform2(rng);
    const Vec3 base(params.patch_size_m * (u.x - 0.5f), params.patch_size_m * (u.y - 0.5f), 0.0f);
    const float heading = kTwoPi * rng.uniform();
    const float length = rng.uniform(params.length_m.x, params.length_m.y);
    // Bend: the tip falls towards `facing` by up to 90° (bend = 1), varied ±30 % per blade.
    const float bend = std::clamp(params.bend * (1.0f + 0.3f * rng.symmetric()), 0.0f, 1.0f);
    const float tilt = 0.15f * rng.symmetric();  // the base leans a little, ±8.6°
    const Vec3 facing(std::cos(heading), std::sin(heading), 0.0f);
    const Vec3 across(-facing.y, facing.x, 0.0f);  // the blade's width direction
    // Control polygon of a blade arching over: the base leg upright (plus tilt), the tip leg turned
    // by the bend angle, legs of a third of the length each (a Bézier's length ≈ its polygon's).
    const float a0 = tilt, a1 = tilt + 0.5f * bend * 0.5f * kPi, a2 = tilt + bend * 0.5f * kPi;
    const auto leg = [&](float angle) {
      return (length / 3.0f) * (std::cos(angle) * Vec3(0, 0, 1) + std::sin(angle) * facing);
    };
    const Vec3 p0 = base, p1 = p0 + leg(a0), p2 = p1 + leg(a1), p3 = p2 + leg(a2);
    const Vec3 p[4] = {p0, p1, p2, p3};
    const float half = 0.5f * params.width_m;
    const float radius[4] = {half, 0.8f * half, 0.5f * half, 0.1f * half};
    for (int k = 0; k < 4; ++k) {
      const Vec3 tangent = k == 0 ? p1 - p0 : k == 3 ? p3 - p2 : p[k + 1] - p[k - 1];
      c.points.emplace_back(p[k], radius[k]);
      c.normals.push_back(glm::normalize(glm::cross(tangent, across)));
    }
  }
  return c;
}

namespace {

// Cubic Bézier basis weights at t and of the derivative.
std::array<float, 4> bezier_weights(float t) {
  const float s = 1.0f - t;
  return {s * s * s, 3.0f * s * s * t, 3.0f * s * t * t, t * t * t};
}

std::array<float, 4> bezier_derivative_weights(float t) {
  const float s = 1.0f - t;
  return {-3.0f * s * s, 3.0f * s * s - 6.0f * s * t, 6.0f * s * t - 3.0f * t * t, 3.0f * t * t};
}

}  // namespace

void tessellate_ribbons(const CurveSet& curves, int segments, std::vector<Vec3>& positions,
                        std::vector<glm::uvec4>& quads) {
  if (segments < 1) throw Error("a ribbon needs at least one segment");
  positions.reserve(positions.size() + curves.size() * 2 * size_t(segments + 1));
  quads.reserve(quads.size() + curves.size() * size_t(segments));
  for (size_t k = 0; k < curves.size(); ++k) {
    const Vec4* cp = &curves.points[4 * k];
    const Vec3* cn = &curves.normals[4 * k];
    const auto first = static_cast<uint32_t>(positions.size());
    Vec3 previous_side(0.0f);
    for (int i = 0; i <= segments; ++i) {
      const float t = static_cast<float>(i) / static_cast<float>(segments);
      const std::array<float, 4> w = bezier_weights(t), dw = bezier_derivative_weights(t);
      Vec4 p(0.0f);
      Vec3 tangent(0.0f), normal(0.0f);
      for (int j = 0; j < 4; ++j) {
        p += w[j] * cp[j];
        tangent += dw[j] * Vec3(cp[j]);
        normal += w[j] * cn[j];
      }
      Vec3 side = glm::cross(tangent, normal);
      const float length = glm::length(side);
      // A degenerate frame (tangent along the normal) keeps the previous station's width direction.
      side = length > 0.0f ? side / length : previous_side;
      previous_side = side;
      positions.push_back(Vec3(p) - p.w * side);
      positions.push_back(Vec3(p) + p.w * side);
    }
    for (int i = 0; i < segments; ++i) {
      // a, a+1 at t_i; a+2, a+3 at t_(i+1): the triangles (a+1, a+3, a) and (a+2, a, a+3), split
      // along the diagonal from a to a+3.
      const uint32_t a = first + 2 * uint32_t(i);
      quads.emplace_back(a + 1, a + 3, a + 2, a);
    }
  }
}

}  // namespace sylva
