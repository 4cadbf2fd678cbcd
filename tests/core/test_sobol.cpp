// The Owen-scrambled Sobol' sampler (core/sobol.h, core/sampler.h): exact stratification of every
// power-of-two prefix and aligned block, uniformity of each sample over scrambles (χ²), independence
// of padded dimensions, unbiased estimates (z-tests) and the faster convergence on a pixel-area and
// a sun-disc integral that is the reason for using it.

#include "core/sampler.h"
#include "core/sampling.h"
#include "core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

namespace sylva {
namespace {

constexpr int kTestsInFile = 4;  // the χ² tests
const double kAlpha = sidak_alpha(0.01, kTestsInFile);

uint32_t cell(float x, int bits) { return static_cast<uint32_t>(x * static_cast<float>(1u << bits)); }

// Every elementary interval of area 2^−m holds exactly one of the 2^m points: a (0,m,2)-net.
bool is_net(const std::vector<Vec2>& points, int m) {
  for (int a = 0; a <= m; ++a) {
    std::vector<int> count(size_t{1} << m, 0);
    for (const Vec2& p : points) ++count[(cell(p.x, a) << (m - a)) | cell(p.y, m - a)];
    for (const int c : count)
      if (c != 1) return false;
  }
  return true;
}

TEST(Sobol, EveryPowerOfTwoPrefixAndAlignedBlockIsANet) {
  for (const uint32_t seed : {0u, 1u, 0xdeadbeefu, 12345u})
    for (int m = 0; m <= 10; ++m)
      for (const uint32_t block : {0u, 1u, 7u}) {  // the first 2^m samples, and later aligned blocks
        std::vector<Vec2> points;
        std::vector<int> strata(size_t{1} << m, 0);
        for (uint32_t i = 0; i < (1u << m); ++i) {
          points.push_back(sobol_2d((block << m) + i, seed));
          ++strata[cell(sobol_1d((block << m) + i, seed), m)];
        }
        EXPECT_TRUE(is_net(points, m)) << "seed " << seed << " m " << m << " block " << block;
        for (const int c : strata) EXPECT_EQ(c, 1) << "1-D: seed " << seed << " m " << m << " block " << block;
      }
}

TEST(Sobol, ShuffleAndScrambleArePermutations) {
  // Distinct indices give distinct shuffled indices and distinct points (no sample is repeated).
  for (const uint32_t seed : {3u, 0x9e3779b9u}) {
    std::vector<bool> seen(1u << 16, false);
    for (uint32_t i = 0; i < (1u << 16); ++i) {
      const uint32_t j = nested_uniform_scramble(i, seed);
      ASSERT_LT(j >> 16, 1u << 16);
      EXPECT_EQ(j >> 16, nested_uniform_scramble(0, seed) >> 16) << "the block of 2^16 maps onto one block";
      seen[j & 0xffffu] = true;
    }
    for (const bool s : seen) EXPECT_TRUE(s);
  }
}

// Sample `index` over many scrambles is uniform on [0, 1)²: χ² on 16 × 16 cells.
TEST(Sobol, EachSampleIsUniformOverScrambles) {
  for (const uint32_t index : {0u, 5u, 1000u}) {
    constexpr int kBins = 16, kN = 256 * 400;
    std::vector<double> observed(kBins * kBins, 0.0), expected(kBins * kBins, kN / double(kBins * kBins));
    for (uint32_t s = 0; s < kN; ++s) {
      const Vec2 p = sobol_2d(index, sobol_seed_hash(s, 77));
      ++observed[cell(p.x, 4) * kBins + cell(p.y, 4)];
    }
    const Chi2Result r = chi2_test(observed, expected);
    EXPECT_GT(r.p_value, kAlpha / 3) << "index " << index << " chi2 " << r.statistic;
  }
}

// Two dimensions of one path (padding) are independent: the pair (dimension A, dimension B) of
// one sample over many pixels is uniform on [0, 1)².
TEST(Sobol, PaddedDimensionsAreIndependent) {
  constexpr int kBins = 16, kN = 256 * 400;
  std::vector<double> observed(kBins * kBins, 0.0), expected(kBins * kBins, kN / double(kBins * kBins));
  Pcg32 unused;
  PathSampler sampler;
  for (uint64_t pixel = 0; pixel < kN; ++pixel) {
    sampler.start(SamplerKind::kSobol, unused, 9, pixel, 3);
    const float a = sampler.get1d(SampleDim::kWavelength);
    sampler.start_event(1);
    const float b = sampler.get1d(SampleDim::kLobe);
    ++observed[cell(a, 4) * kBins + cell(b, 4)];
  }
  const Chi2Result r = chi2_test(observed, expected);
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
}

TEST(Sobol, SamplesDependOnSeedPixelIndexAndDimensionOnly) {
  Pcg32 unused;
  PathSampler a, b;
  a.start(SamplerKind::kSobol, unused, 5, 1234, 17);
  b.start(SamplerKind::kSobol, unused, 5, 1234, 17);
  b.start_event(4);  // other events drawn first change nothing
  (void)b.get2d(SampleDim::kScatter);
  b.start_event(0);
  EXPECT_EQ(a.get2d(SampleDim::kPixel), b.get2d(SampleDim::kPixel));
  EXPECT_NE(a.get1d(SampleDim::kWavelength), a.get1d(SampleDim::kLobe));
  b.start(SamplerKind::kSobol, unused, 6, 1234, 17);
  a.start(SamplerKind::kSobol, unused, 5, 1234, 17);
  EXPECT_NE(a.get2d(SampleDim::kPixel), b.get2d(SampleDim::kPixel)) << "another seed, other points";
}

TEST(Sobol, IndependentSamplerDrawsThePcg32Stream) {
  // The bits of every render before the Sobol' sampler: PCG32 from hash_ids(seed, pixel, index),
  // 2-D draws in uniform2's order.
  Pcg32 rng, expected(hash_ids(uint64_t{5}, uint64_t{77}, uint32_t{3}));
  PathSampler s;
  s.start(SamplerKind::kIndependent, rng, 5, 77, 3);
  const Vec2 p = s.get2d(SampleDim::kPixel);
  const float w = s.get1d(SampleDim::kWavelength);
  EXPECT_EQ(p, uniform2(expected));
  EXPECT_EQ(w, expected.uniform());
}

TEST(Sobol, SeveralDrawsOfOneUseStratifyTogether) {
  // Draw j of n at one event (several light samples at a vertex): the pixel's first 2^m samples'
  // n draws each are together a (0, m + log2 n, 2)-net, and draw 0 of 1 is the plain draw.
  Pcg32 unused;
  PathSampler s;
  for (const uint32_t n : {1u, 2u, 4u, 8u})
    for (int m = 0; m <= 6; ++m) {
      std::vector<Vec2> points;
      for (uint32_t i = 0; i < (1u << m); ++i) {
        s.start(SamplerKind::kSobol, unused, 9, 4321, i);
        s.start_event(1);
        for (uint32_t j = 0; j < n; ++j) points.push_back(s.get2d(SampleDim::kLight, j, n));
      }
      EXPECT_TRUE(is_net(points, m + static_cast<int>(std::log2(n)))) << "n " << n << " m " << m;
    }
  PathSampler a, b;
  a.start(SamplerKind::kSobol, unused, 9, 4321, 5);
  b.start(SamplerKind::kSobol, unused, 9, 4321, 5);
  EXPECT_EQ(a.get2d(SampleDim::kLight), b.get2d(SampleDim::kLight, 0, 1));
  EXPECT_EQ(a.get1d(SampleDim::kLightSelect), b.get1d(SampleDim::kLightSelect, 0, 1));
}

// The estimates of ∫ f over [0, 1)² with n points of one pixel's sequence, over `runs` pixels: their
// mean error in standard errors (z) and their root mean squared error.
struct Convergence {
  double z = 0, rmse = 0;
};
Convergence estimate(SamplerKind kind, int n, int runs, const std::function<double(Vec2)>& f, double exact) {
  double sum = 0, sum2 = 0;
  Pcg32 rng;
  PathSampler sampler;
  for (int r = 0; r < runs; ++r) {
    double e = 0;
    for (int i = 0; i < n; ++i) {
      sampler.start(kind, rng, 11, static_cast<uint64_t>(r), static_cast<uint32_t>(i));
      e += f(sampler.get2d(SampleDim::kPixel));
    }
    e = e / n - exact;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / runs, var = (sum2 - runs * mean * mean) / (runs - 1);
  return {mean / std::sqrt(var / runs), std::sqrt(sum2 / runs)};
}

// A pixel crossed by an edge (the fraction of its area below y = 0.3 + 0.4 x: 1/2), and the sun's
// disc (0.27° radius) behind a vertical edge at 0.3 of its radius from its centre, seen through the
// cone sampler (the visible fraction of a disc, 1 − (acos a − a √(1 − a²))/π for a = 0.3; the cap is
// a flat disc to 10⁻⁵): discontinuous integrands, where Owen-scrambled nets converge as n^−3/4
// against n^−1/2.
double edge(Vec2 u) { return u.y < 0.3f + 0.4f * u.x ? 1.0 : 0.0; }
constexpr double kSunRadius = 0.27 * kPi / 180.0;
double sun_behind_edge(Vec2 u) {
  const Vec3 d = sample_uniform_cone(u, one_minus_cos(static_cast<float>(kSunRadius)));
  return d.x < 0.3 * std::sin(kSunRadius) ? 1.0 : 0.0;
}
const double kSunVisible = 1.0 - (std::acos(0.3) - 0.3 * std::sqrt(1.0 - 0.09)) / kPi;
// A smooth integrand (a lit pixel's gradient): n^−3/2 against n^−1/2.
double smooth(Vec2 u) { return std::exp(u.x) * std::sin(2.0 * u.y) + u.x * u.y; }
const double kSmoothExact = (std::exp(1.0) - 1.0) * (1.0 - std::cos(2.0)) / 2.0 + 0.25;

TEST(Sobol, UnbiasedAndConvergesFasterThanIndependent) {
  struct Case {
    const char* name;
    std::function<double(Vec2)> f;
    double exact, min_rate;  // the RMSE's decay exponent must exceed min_rate (independent: 0.5)
  };
  const Case cases[] = {{"edge", edge, 0.5, 0.65},
                        {"sun behind an edge", sun_behind_edge, kSunVisible, 0.65},
                        {"smooth", smooth, kSmoothExact, 1.2}};
  for (const Case& c : cases) {
    const Convergence low = estimate(SamplerKind::kSobol, 16, 512, c.f, c.exact);
    const Convergence high = estimate(SamplerKind::kSobol, 1024, 512, c.f, c.exact);
    const double rate = std::log(low.rmse / high.rmse) / std::log(1024.0 / 16.0);
    EXPECT_GT(rate, c.min_rate) << c.name << ": RMSE " << low.rmse << " at 16, " << high.rmse << " at 1024";
    EXPECT_LT(std::abs(low.z), 4.0) << c.name << " biased at 16 samples";
    EXPECT_LT(std::abs(high.z), 4.0) << c.name << " biased at 1024 samples";
    const Convergence independent = estimate(SamplerKind::kIndependent, 1024, 512, c.f, c.exact);
    EXPECT_LT(std::abs(independent.z), 4.0) << c.name;
    EXPECT_LT(high.rmse, 0.5 * independent.rmse) << c.name << ": Sobol' must beat independent at 1024 samples";
  }
}

}  // namespace
}  // namespace sylva
