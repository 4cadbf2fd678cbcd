#include "geometry/grass.h"

#include "core/error.h"
#include "core/rng.h"

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
    const Vec3 base(params.patch_size_m * (rng.uniform() - 0.5f), params.patch_size_m * (rng.uniform() - 0.5f), 0.0f);
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

}  // namespace sylva
