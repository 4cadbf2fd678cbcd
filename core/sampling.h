#pragma once
// Sampling routines: warps from [0,1)² and tabulated distributions. Each has a pdf function and a
// χ² test in tests/core/test_sampling.cpp.

#include "core/fast_math.h"
#include "core/math.h"

#include <vector>

namespace sylva {

// Uniform point on the unit disc (concentric map, Shirley & Chiu 1997). Inline: every diffuse
// bounce takes one.
inline Vec2 sample_uniform_disk(Vec2 u) {
  const Vec2 o = 2.0f * u - Vec2(1.0f);
  if (o.x == 0 && o.y == 0) return Vec2(0.0f);
  // θ = (π/4)·(o.y/o.x), or π/2 − (π/4)·(o.x/o.y): both from sin and cos of an angle in [−π/4, π/4].
  // Which of the two is a random choice: selected, not branched on.
  const bool wide = std::abs(o.x) > std::abs(o.y);
  const float r = select(wide, o.x, o.y);
  const SinCos sc = sincos_quarter((kPi / 4) * (select(wide, o.y, o.x) / r));
  return r * Vec2(select(wide, sc.cos, sc.sin), select(wide, sc.sin, sc.cos));
}

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
  return spherical_direction_fast(sin_theta, 1.0f - one_minus_cos, kTwoPi * u.y);
}
inline float uniform_cone_pdf(float one_minus_cos_max) { return 1.0f / (kTwoPi * one_minus_cos_max); }
inline float one_minus_cos(float half_angle_rad) { return 2.0f * sqr(std::sin(0.5f * half_angle_rad)); }

// Uniform direction on the sphere; pdf = 1 / 4π.
inline Vec3 sample_uniform_sphere(Vec2 u) {
  const float z = 1.0f - 2.0f * u.x;
  return spherical_direction(safe_sqrt(1.0f - z * z), z, kTwoPi * u.y);
}

// One bin of a tabulated distribution: where its cumulative mass starts and its density, side by
// side so the sampler's search and the density it returns share a cache line (these tables are
// read once per wavelength and sky sample, usually after Embree's traversal has evicted them).
struct DistributionBin {
  float cdf = 0;  // cumulative mass before the bin, in [0, 1]
  float pdf = 0;  // density on [0, 1) over the bin
};

// The bin of n equal bins over [0, 1) that holds x (clamped to the first and last).
inline int bin_index(float x, int n) { return std::clamp(static_cast<int>(x * static_cast<float>(n)), 0, n - 1); }

// Inverse-CDF sampling over n bins of `bins` (n + 1 entries, the last {1, 0}) with the cut-point
// guide table `guide` (guide[k]: last bin whose cdf start ≤ k/n): the continuous sample in [0, 1),
// its density and its bin.
inline float sample_bins(const DistributionBin* bins, const uint32_t* guide, int n, float u, float* pdf, int* bin) {
  // Last bin whose cdf start is <= u (found from the guide table: O(1) on average), then back over
  // bins with no mass.
  int i = static_cast<int>(guide[bin_index(u, n)]);
  while (i > 0 && bins[i].cdf > u) --i;
  while (i + 1 < n && bins[i + 1].cdf <= u) ++i;
  while (i > 0 && bins[i + 1].cdf == bins[i].cdf) --i;
  const float width = bins[i + 1].cdf - bins[i].cdf;
  const float du = width > 0 ? (u - bins[i].cdf) / width : 0.5f;
  if (pdf) *pdf = bins[i].pdf;
  if (bin) *bin = i;
  return std::min((static_cast<float>(i) + std::clamp(du, 0.0f, 1.0f)) / static_cast<float>(n), 0x1.fffffep-1f);
}

// Piecewise-constant 1-D distribution over [0, 1) with n equal bins.
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(const std::vector<float>& weights);

  // Continuous sample in [0,1); `pdf` is the density on [0,1); `bin` the chosen bin.
  float sample(float u, float* pdf, int* bin = nullptr) const {
    return sample_bins(bins_.data(), guide_.data(), size(), u, pdf, bin);
  }
  float pdf(float x) const { return bin_pdf(bin_of(x)); }
  // The density on [0,1) over bin i, and the bin holding x.
  float bin_pdf(int i) const { return bins_[i].pdf; }
  int bin_of(float x) const { return bin_index(x, size()); }
  int size() const { return static_cast<int>(guide_.size()); }
  float integral() const { return integral_; }  // mean of the weights

  // The tables of `weights` (n of them) written into bins[0..n] and guide[0..n); returns the mean
  // weight. Distribution2D keeps its rows' tables in one array this way.
  static float tabulate(const float* weights, int n, DistributionBin* bins, uint32_t* guide);

 private:
  std::vector<DistributionBin> bins_;  // n + 1
  std::vector<uint32_t> guide_;        // n
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
  Distribution1D marginal_;
  int nu_ = 0;
  // Row v's conditional tables, in one array each (no per-row header).
  DistributionBin* row_bins(int v) { return row_bins_.data() + static_cast<size_t>(v) * (nu_ + 1); }
  const DistributionBin* row_bins(int v) const { return row_bins_.data() + static_cast<size_t>(v) * (nu_ + 1); }
  uint32_t* row_guide(int v) { return row_guides_.data() + static_cast<size_t>(v) * nu_; }
  const uint32_t* row_guide(int v) const { return row_guides_.data() + static_cast<size_t>(v) * nu_; }

  std::vector<DistributionBin> row_bins_;
  std::vector<uint32_t> row_guides_;
  std::vector<float> pdf_;  // per cell (row-major): the marginal's density times the row's, one lookup
};

}  // namespace sylva
