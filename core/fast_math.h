#pragma once
// sin and cos, atan2, acos and exp in float, inline and without libm's calls: for the samplers and
// the sky, which evaluate them once or twice per bounce (bench/README.md, "Wavelengths from one
// table entry, trigonometry inline"). Each is within a few 10⁻⁷ of the exact value (absolute
// for sin, cos, atan2 and acos; relative for exp) over the domain stated;
// tests/core/test_fast_math.cpp measures them against double precision. Geometry keeps the
// standard functions, so a tree's shape does not depend on these.

#include "core/math.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace sylva {

struct SinCos {
  float sin, cos;
};

// sin r and cos r for |r| ≤ π/4: minimax polynomials (the coefficients of Moshier's Cephes sinf and
// cosf).
inline SinCos sincos_quarter(float r) {
  const float r2 = r * r;
  const float s = r + r * r2 * (-1.6666654611e-1f + r2 * (8.3321608736e-3f + r2 * -1.9515295891e-4f));
  const float c =
      1.0f - 0.5f * r2 + r2 * r2 * (4.166664568298827e-2f + r2 * (-1.388731625493765e-3f + r2 * 2.443315711809948e-5f));
  return {s, c};
}

// sin x and cos x for |x| ≤ 8π (the samplers pass angles in [−2π, 2π]).
inline SinCos sincos_fast(float x) {
  // The quadrant j = round(x / (π/2)) and r = x − j·π/2, with π/2 in three parts (Cody & Waite) so
  // that j·part is exact for the first two and r keeps its precision.
  const auto j = static_cast<int>(x * 0.63661977f + std::copysign(0.5f, x));
  const auto fj = static_cast<float>(j);
  const float r = ((x - fj * 1.5703125f) - fj * 4.837512969970703125e-4f) - fj * 7.54978995489188216e-8f;
  const SinCos q0 = sincos_quarter(r);
  // sin(r + jπ/2), cos(r + jπ/2): quadrants 1 and 3 swap the two, 2 and 3 negate sin, 1 and 2 cos.
  const auto q = static_cast<unsigned>(j) & 3u;
  const float sin_x = select(q & 1u, q0.cos, q0.sin), cos_x = select(q & 1u, q0.sin, q0.cos);
  return {select(q & 2u, -sin_x, sin_x), select((q + 1u) & 2u, -cos_x, cos_x)};
}

// atan2(y, x) in [−π, π] for finite x, y (0 when both are 0).
inline float atan2_fast(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float big = std::max(ax, ay), small = std::min(ax, ay);
  const float a = big > 0 ? small / big : 0.0f;  // in [0, 1]
  // atan a: above tan(π/8), π/4 + atan((a − 1)/(a + 1)); a minimax polynomial for |t| ≤ tan(π/8)
  // (the coefficients of Cephes atanf).
  const bool upper = a > 0.41421356f;
  const float t = select(upper, (a - 1.0f) / (a + 1.0f), a);
  const float z = t * t;
  float r = (((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f) * z * t + t;
  r = select(upper, r + 0.25f * kPi, r);
  r = select(ay > ax, 0.5f * kPi - r, r);
  r = select(x < 0, kPi - r, r);
  return std::copysign(r, y);
}

// acos x for x in [−1, 1] (clamped): Abramowitz & Stegun 4.4.46, √(1 − |x|)·P₇(|x|), error ≤ 2·10⁻⁸
// in exact arithmetic.
inline float acos_fast(float x) {
  const float a = std::min(std::abs(x), 1.0f);
  float p = -0.0012624911f;
  p = p * a + 0.0066700901f;
  p = p * a - 0.0170881256f;
  p = p * a + 0.0308918810f;
  p = p * a - 0.0501743046f;
  p = p * a + 0.0889789874f;
  p = p * a - 0.2145988016f;
  p = p * a + 1.5707963050f;
  const float r = std::sqrt(1.0f - a) * p;
  return select(x < 0, kPi - r, r);
}

// e^x for x ≤ 88 (0 below −87.3, where e^x leaves the normal floats).
inline float exp_fast(float x) {
  if (!(x >= -87.3f)) return 0.0f;
  x = std::min(x, 88.0f);
  // e^x = 2^i · e^y with i = round(x / ln 2) and |y| ≤ ln 2 / 2 (in double), e^y by its Taylor
  // polynomial of degree 6 (remainder below 2·10⁻⁷ of the value).
  const double xd = x;
  const auto i = static_cast<int32_t>(xd * 1.4426950408889634 + std::copysign(0.5, xd));
  const auto y = static_cast<float>(xd - static_cast<double>(i) * 0.69314718055994531);
  const float p =
      1.0f + y * (1.0f + y * (0.5f + y * (1.0f / 6 + y * (1.0f / 24 + y * (1.0f / 120 + y * (1.0f / 720))))));
  // 2^i for i in [−126, 127]: the exponent field alone.
  return p * std::bit_cast<float>(static_cast<uint32_t>(i + 127) << 23);
}

// spherical_direction and spherical_phi (core/math.h) through the functions above: the samplers'
// directions and the sky's table lookups.
inline Vec3 spherical_direction_fast(float sin_theta, float cos_theta, float phi) {
  const SinCos sc = sincos_fast(phi);
  return spherical_direction(sin_theta, cos_theta, sc.sin, sc.cos);
}
inline float spherical_phi_fast(const Vec3& d) { return azimuth_from_atan2(atan2_fast(d.y, d.x)); }

}  // namespace sylva
