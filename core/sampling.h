#pragma once
// Sampling routines: warps from [0,1)² and tabulated distributions. Each has a pdf function and a
// χ² test in tests/core/test_sampling.cpp.

#include "core/math.h"

#include <vector>

namespace sylva {

// Uniform point on the unit disc (concentric map, Shirley & Chiu 1997).
Vec2 sample_uniform_disk(Vec2 u);

// Cosine-weighted direction about +Z (Malley's method); pdf = cos θ / π (per steradian).
inline Vec3 sample_cosine_hemisphere(Vec2 u) {
  const Vec2 d = sample_uniform_disk(u);
  return {d.x, d.y, safe_sqrt(1.0f - d.x * d.x - d.y * d.y)};
}
inline float cosine_hemisphere_pdf(float cos_theta) { return std::max(0.0f, cos_theta) * kInvPi; }

// Uniform direction in the cone of half-angle α about +Z, given 1 − cos α (= 2 sin²(α/2), exact
// for tiny cones such as the 0.27° sun where cos α rounds in float); pdf = 1 / (2π(1 − cos α)).
inline Vec3 sample_uniform_cone(Vec2 u, float one_minus_cos_max) {
  const float one_minus_cos = u.x * one_minus_cos_max;
  const float sin_theta = safe_sqrt(one_minus_cos * (2.0f - one_minus_cos));
  return spherical_direction(sin_theta, 1.0f - one_minus_cos, kTwoPi * u.y);
}
inline float uniform_cone_pdf(float one_minus_cos_max) { return 1.0f / (kTwoPi * one_minus_cos_max); }
inline float one_minus_cos(float half_angle_rad) { return 2.0f * sqr(std::sin(0.5f * half_angle_rad)); }

// Uniform direction on the sphere; pdf = 1 / 4π.
inline Vec3 sample_uniform_sphere(Vec2 u) {
  const float z = 1.0f - 2.0f * u.x;
  return spherical_direction(safe_sqrt(1.0f - z * z), z, kTwoPi * u.y);
}

// Piecewise-constant 1-D distribution over [0, 1) with n equal bins.
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(std::vector<float> weights);

  // Continuous sample in [0,1); `pdf` is the density on [0,1); `bin` the chosen bin.
  float sample(float u, float* pdf, int* bin = nullptr) const;
  float pdf(float x) const { return bin_pdf(bin_of(x)); }
  // The density on [0,1) over bin i, and the bin holding x.
  float bin_pdf(int i) const { return integral_ > 0 ? std::max(0.0f, weights_[i]) / integral_ : 1.0f; }
  int bin_of(float x) const { return std::clamp(static_cast<int>(x * static_cast<float>(size())), 0, size() - 1); }
  int size() const { return static_cast<int>(weights_.size()); }
  float integral() const { return integral_; }  // mean of the weights
  float weight(int i) const { return weights_[i]; }

 private:
  std::vector<float> weights_;
  std::vector<float> cdf_;  // size n+1
  std::vector<int> guide_;  // guide_[k]: last bin whose cdf start ≤ k/n (cut-point search)
  float integral_ = 0;
};

// Piecewise-constant 2-D distribution over [0,1)², rows indexed by v, columns by u.
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<float>& weights, int nu, int nv);

  Vec2 sample(Vec2 u, float* pdf) const;
  float pdf(Vec2 p) const;

 private:
  std::vector<Distribution1D> conditional_;
  Distribution1D marginal_;
  int nu_ = 0;
  std::vector<float> pdf_;  // per cell (row-major): the marginal's density times the row's, one lookup
};

}  // namespace sylva
