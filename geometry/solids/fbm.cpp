#include "geometry/solids/fbm.h"

#include "core/hash.h"

#include <cmath>

namespace sylva {

namespace {

// The lattice value at integer point (x, y, z), uniform in [−1, 1].
// One mix64 of the coordinates folded with large odd multipliers (the sphere tracer evaluates this
// eight times per octave per step, so it is kept to a single finaliser).
float lattice(int64_t x, int64_t y, int64_t z, uint64_t seed) {
  const uint64_t h =
      mix64(seed ^ (static_cast<uint64_t>(x) * 0x9e3779b97f4a7c15ull) ^
            (static_cast<uint64_t>(y) * 0xc2b2ae3d27d4eb4full) ^ (static_cast<uint64_t>(z) * 0x165667b19e3779f9ull));
  return static_cast<float>(h >> 40) * 0x1p-23f - 1.0f;
}

float smoothstep(float t) { return t * t * (3.0f - 2.0f * t); }

}  // namespace

float value_noise(const Vec3& p, uint64_t seed) {
  const float fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  const auto ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy), iz = static_cast<int64_t>(fz);
  const float sx = smoothstep(p.x - fx), sy = smoothstep(p.y - fy), sz = smoothstep(p.z - fz);
  float c[2][2];
  for (int j = 0; j < 2; ++j)
    for (int k = 0; k < 2; ++k) {
      const float a = lattice(ix, iy + j, iz + k, seed), b = lattice(ix + 1, iy + j, iz + k, seed);
      c[j][k] = a + sx * (b - a);
    }
  const float y0 = c[0][0] + sy * (c[1][0] - c[0][0]);
  const float y1 = c[0][1] + sy * (c[1][1] - c[0][1]);
  return y0 + sz * (y1 - y0);
}

float fbm(const FbmParams& params, const Vec3& p) {
  const float g = std::pow(params.lacunarity, -params.hurst);
  float sum = 0.0f, norm = 0.0f, amplitude = 1.0f, frequency = 1.0f / params.wavelength_m;
  for (int k = 0; k < params.octaves; ++k) {
    sum += amplitude * value_noise(p * frequency, hash_ids(params.seed, static_cast<uint64_t>(k)));
    norm += amplitude;
    amplitude *= g;
    frequency *= params.lacunarity;
  }
  return sum / norm;
}

// Proof of the bound. Inside a lattice cell, v = Σ_corners val_c Π_i w_i(c_i) with w_i(1) = S(t_i),
// w_i(0) = 1 − S(t_i), S(t) = 3t² − 2t³ ∈ [0, 1]. Then
//   ∂v/∂t_x = S'(t_x) Σ_{c_y,c_z} (val(1,c_y,c_z) − val(0,c_y,c_z)) w_y w_z,
// a convex combination (the weights w_y w_z are non-negative and sum to 1) of differences of two
// values in [−1, 1], times S'(t) = 6t(1 − t) ≤ 3/2; so |∂v/∂t_i| ≤ 3 and |∇v| ≤ 3√3. v is
// continuous across cell faces (both sides interpolate the same face values), so along any segment
// it is piecewise C¹ and |v(p) − v(q)| ≤ 3√3 |p − q|. Octave k is v(f_k p) with f_k = λ^k / s,
// Lipschitz 3√3 f_k; the sum over octaves with weights g^k / Σ g^j is Lipschitz with
//   L = 3√3 Σ_k g^k f_k / Σ_k g^k.
// tests/geometry/test_solids.cpp checks that no sampled difference quotient exceeds L.
float fbm_lipschitz(const FbmParams& params) {
  const float g = std::pow(params.lacunarity, -params.hurst);
  double sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0 / params.wavelength_m;
  for (int k = 0; k < params.octaves; ++k) {
    sum += amplitude * frequency;
    norm += amplitude;
    amplitude *= g;
    frequency *= params.lacunarity;
  }
  return static_cast<float>(3.0 * std::sqrt(3.0) * sum / norm);
}

}  // namespace sylva
