// χ² tests of the core sampling routines (10⁶ samples each, Šidák-corrected over this file).

#include "core/band.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/statistics.h"
#include "tests/support/chi2_directions.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

constexpr int kTestsInFile = 8;
const double kAlpha = sidak_alpha(0.01, kTestsInFile);

Vec2 u2(Pcg32& rng) { return {rng.uniform(), rng.uniform()}; }

TEST(Sampling, CosineHemisphereChi2) {
  Pcg32 rng(1);
  const auto r = test::chi2_directions(
      {}, [&](int) { return sample_cosine_hemisphere(u2(rng)); },
      [](const Vec3& d) { return cosine_hemisphere_pdf(d.z); });
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic << " dof " << r.dof;
}

TEST(Sampling, UniformConeChi2) {
  Pcg32 rng(2);
  const float cos_max = 0.75f;  // on a bin edge of the harness (multiples of 1/16 in cos θ)
  const auto r = test::chi2_directions(
      {}, [&](int) { return sample_uniform_cone(u2(rng), 1.0f - cos_max); },
      [&](const Vec3& d) { return d.z >= cos_max ? uniform_cone_pdf(1.0f - cos_max) : 0.0; });
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
}

TEST(Sampling, UniformSphereChi2) {
  Pcg32 rng(3);
  const auto r = test::chi2_directions(
      {}, [&](int) { return sample_uniform_sphere(u2(rng)); }, [](const Vec3&) { return kInvFourPi; });
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
}

TEST(Sampling, ChiSquareDetectsAWrongPdf) {
  // The harness must be able to fail: cosine samples against a uniform-hemisphere pdf.
  Pcg32 rng(4);
  const auto r = test::chi2_directions(
      {}, [&](int) { return sample_cosine_hemisphere(u2(rng)); },
      [](const Vec3& d) { return d.z > 0 ? 0.5 * kInvPi : 0.0; });
  EXPECT_LT(r.p_value, 1e-6);
}

TEST(Sampling, Distribution1DChi2) {
  const std::vector<float> w = {0.0f, 1.0f, 3.0f, 0.5f, 0.0f, 2.0f, 7.0f, 0.25f};
  const Distribution1D d(w);
  Pcg32 rng(5);
  constexpr int n = 1'000'000, bins = 64;
  std::vector<double> obs(bins, 0.0), exp(bins, 0.0);
  for (int i = 0; i < n; ++i) {
    float pdf = 0;
    const float x = d.sample(rng.uniform(), &pdf);
    ASSERT_GT(pdf, 0.0f);
    ASSERT_NEAR(pdf, d.pdf(x), 1e-5f);
    obs[std::min(bins - 1, static_cast<int>(x * bins))] += 1;
  }
  for (int b = 0; b < bins; ++b) exp[b] = n * d.pdf((b + 0.5f) / bins) / bins;
  const auto r = chi2_test(obs, exp);
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
}

TEST(Sampling, Distribution2DChi2) {
  constexpr int nu = 8, nv = 6;
  std::vector<float> w(nu * nv);
  Pcg32 g(6);
  for (float& x : w) x = g.uniform() < 0.2f ? 0.0f : g.uniform();
  const Distribution2D d(w, nu, nv);
  Pcg32 rng(7);
  constexpr int n = 1'000'000, ru = 4 * nu, rv = 5 * nv;  // histogram cells nest in the distribution's
  std::vector<double> obs(ru * rv, 0.0), exp(ru * rv, 0.0);
  for (int i = 0; i < n; ++i) {
    float pdf = 0;
    const Vec2 p = d.sample(u2(rng), &pdf);
    ASSERT_GT(pdf, 0.0f);
    obs[std::min(rv - 1, int(p.y * rv)) * ru + std::min(ru - 1, int(p.x * ru))] += 1;
  }
  for (int j = 0; j < rv; ++j)
    for (int i = 0; i < ru; ++i) exp[j * ru + i] = n * d.pdf(Vec2((i + 0.5f) / ru, (j + 0.5f) / rv)) / (ru * rv);
  const auto r = chi2_test(obs, exp);
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
}

// χ² of n hero wavelengths from `bands` against the sampler's own pdf over [lo, hi) nm, each
// sample's pdf being pdf(λ); every channel weight covered (w_c ≠ 0 ⇒ pdf > 0).
void expect_wavelengths_follow_pdf(const std::vector<Band>& bands, float lo, float hi, int bins) {
  const WavelengthSampler s(bands);
  Pcg32 rng(8);
  constexpr int n = 1'000'000;  // 4 wavelengths per draw: each marginally distributed by the pdf
  std::vector<double> obs(bins, 0.0), exp(bins, 0.0);
  for (int i = 0; i < n; ++i) {
    const SampledWavelengths wl = s.sample(rng.uniform(), rng.uniform());
    const float l = wl.lambda_nm[i % kLambdaCount];
    ASSERT_GT(wl.pdf[i % kLambdaCount], 0.0f);
    ASSERT_EQ(wl.pdf[i % kLambdaCount], s.pdf(l)) << l;
    if (l >= lo && l < hi) obs[static_cast<int>((l - lo) / (hi - lo) * bins)] += 1;
  }
  for (int b = 0; b < bins; ++b) {
    double integral = 0;
    const double w = (hi - lo) / bins;
    for (int k = 0; k < 20; ++k) integral += s.pdf(lo + (b + (k + 0.5) / 20) * w) * w / 20;
    exp[b] = n * integral;
  }
  const auto r = chi2_test(obs, exp);
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
  for (const Band& b : bands)
    for (const DenseSpectrum& w : b.weights)
      for (int i = 0; i < kLambdaSamples - 1; ++i)
        if (w[i] != 0) {
          ASSERT_GT(s.pdf(DenseSpectrum::grid_lambda(i) + 0.5f), 0.0f) << b.name << " at " << i;
        }
}

TEST(Sampling, WavelengthSamplerChi2AndCoverage) {
  expect_wavelengths_follow_pdf({resolve_band("rgb"), resolve_band("nir")}, 300, 1200, 180);
}

// A spike on a faint 1 000 nm floor: most of the sampler's cells lie in the spike's few bins, and a
// cell in the floor spans many bins (the sampler's search beyond a cell's two bins).
TEST(Sampling, WavelengthSamplerSpikeOnFaintFloor) {
  DenseSpectrum response;
  for (int i = 0; i < kLambdaSamples; ++i) {
    const float l = DenseSpectrum::grid_lambda(i);
    response[i] = l >= 400 && l <= 1400 ? (l >= 550 && l <= 552 ? 1.0f : 1e-5f) : 0.0f;
  }
  expect_wavelengths_follow_pdf({make_srf_band("spike", response)}, 390, 1410, 204);
  const WavelengthSampler s({make_srf_band("spike", response)});
  // The density is the importance's, to the float CDF's resolution (6·10⁻⁸ in u: 2 % of a floor
  // bin's mass of 3·10⁻⁶; what a uniform u then picks it with).
  EXPECT_NEAR(s.pdf(551.0f) / s.pdf(900.0f), 1e5, 1e5 * 0.02);
}

TEST(Sampling, HeroWavelengthsAreStratified) {
  const WavelengthSampler s({resolve_band("rgb")});
  const SampledWavelengths wl = s.sample(0.1f, 0.5f);
  for (int i = 1; i < kLambdaCount; ++i) EXPECT_NE(wl.lambda_nm[i], wl.lambda_nm[0]);
}

// The vector draws have one order on every compiler (core/rng.h): last coordinate first, the order
// the recorded trees and golden images were made with. A change here changes every tree.
TEST(Rng, VectorDrawsHaveAFixedOrder) {
  Pcg32 a(7), b(7);
  const Vec3 u = uniform3(a);
  const float first = b.uniform(), second = b.uniform(), third = b.uniform();
  EXPECT_EQ(u, Vec3(third, second, first));
  EXPECT_EQ(a.next_u32(), b.next_u32());  // exactly three draws
  const Vec2 s = symmetric2(a);
  const float s_first = b.symmetric(), s_second = b.symmetric();
  EXPECT_EQ(s, Vec2(s_second, s_first));
}

TEST(Statistics, Chi2SurvivalMatchesKnownValues) {
  EXPECT_NEAR(chi2_survival(3.841, 1), 0.05, 1e-3);
  EXPECT_NEAR(chi2_survival(18.307, 10), 0.05, 1e-3);
  EXPECT_NEAR(chi2_survival(124.342, 100), 0.05, 1e-3);
  EXPECT_NEAR(sidak_alpha(0.01, 1), 0.01, 1e-12);
}

}  // namespace
}  // namespace sylva
