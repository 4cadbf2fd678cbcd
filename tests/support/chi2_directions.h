#pragma once
// A χ² test harness for direction samplers (after Mitsuba 3's and pbrt-v4's): sample N directions,
// histogram them over an equal-area (cos θ, φ) grid of the sphere, integrate the claimed pdf over
// each cell numerically, and run Pearson's test.

#include "core/math.h"
#include "core/statistics.h"

#include <functional>
#include <vector>

namespace sylva::test {

struct DirectionChi2 {
  int theta_bins = 32;  // in cos θ ∈ [-1, 1]
  int phi_bins = 64;
  int samples = 1'000'000;
  int integration_res = 8;  // sub-cells per bin side for integrating the pdf
};

// `sample(i)` returns a direction, or a zero vector for "no sample" (counted as lost mass).
// `pdf(d)` is the density per steradian. Returns the χ² result; the expected total is
// samples × ∫pdf, so a pdf that does not integrate to the sampled mass fails too.
inline Chi2Result chi2_directions(const DirectionChi2& cfg, const std::function<Vec3(int)>& sample,
                                  const std::function<double(const Vec3&)>& pdf) {
  const int nt = cfg.theta_bins, np = cfg.phi_bins;
  std::vector<double> observed(static_cast<size_t>(nt) * np + 1, 0.0), expected(observed.size(), 0.0);
  auto cell = [&](const Vec3& d) {
    const float z = std::clamp(d.z, -1.0f, 1.0f);
    float phi = std::atan2(d.y, d.x);
    if (phi < 0) phi += kTwoPi;
    const int t = std::clamp(static_cast<int>((z + 1.0f) * 0.5f * nt), 0, nt - 1);
    const int p = std::clamp(static_cast<int>(phi / kTwoPi * np), 0, np - 1);
    return static_cast<size_t>(t) * np + p;
  };
  const size_t lost = observed.size() - 1;
  for (int i = 0; i < cfg.samples; ++i) {
    const Vec3 d = sample(i);
    if (d == Vec3(0.0f))
      observed[lost] += 1;
    else
      observed[cell(d)] += 1;
  }
  // Integrate the pdf over each cell by the midpoint rule in (cos θ, φ), where dω = d(cos θ) dφ: exact
  // for a pdf constant on (cos θ, φ) cells that the sub-cells nest in (the sky's 256 × 128 table:
  // the default 32 × 64 bins and 8 × 8 sub-cells align with it) and accurate for smooth ones.
  const int k = cfg.integration_res;
  const double dz = 2.0 / nt / k, dphi = 2.0 * M_PI / np / k;
  double total = 0;
  for (int t = 0; t < nt; ++t)
    for (int p = 0; p < np; ++p) {
      double sum = 0;
      for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b) {
          const double z = -1.0 + (t * k + a + 0.5) * dz, s = std::sqrt(std::max(0.0, 1.0 - z * z));
          const double ph = (p * k + b + 0.5) * dphi;
          sum += pdf(
              Vec3(static_cast<float>(s * std::cos(ph)), static_cast<float>(s * std::sin(ph)), static_cast<float>(z)));
        }
      const double e = sum * dz * dphi * cfg.samples;
      expected[static_cast<size_t>(t) * np + p] = e;
      total += e;
    }
  expected[lost] = std::max(0.0, cfg.samples - total);
  return chi2_test(observed, expected);
}

}  // namespace sylva::test
