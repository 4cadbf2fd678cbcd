// Materials: χ² of the leaf BSDF sampler (reflection and transmission), energy, validation.

#include "core/error.h"
#include "core/rng.h"
#include "render/materials/material.h"
#include "tests/support/chi2_directions.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

const double kMaterialAlpha = sidak_alpha(0.01, 4);

SampledWavelengths wl550() {
  SampledWavelengths wl;
  wl.lambda_nm = SampledSpectrum(550.0f);
  return wl;
}

// The material's BSDF at a hit seen from `front` (the integrator's context, the position unused).
Bsdf bsdf_at(const Material& m, const SampledWavelengths& wl, bool front) {
  HitContext ctx;
  ctx.front = front;
  ctx.wl = &wl;
  return material_bsdf(m, ctx);
}

Chi2Result chi2_bsdf(const Material& m, const Vec3& wo, bool front, uint64_t seed) {
  const SampledWavelengths wl = wl550();
  const Bsdf bsdf = bsdf_at(m, wl, front);
  Pcg32 rng(seed);
  return test::chi2_directions(
      {},
      [&](int) {
        BsdfSample s;
        if (!bsdf.sample(wo, Vec2(rng.uniform(), rng.uniform()), rng.uniform(), &s)) return Vec3(0.0f);
        EXPECT_NEAR(s.pdf, bsdf.pdf(wo, s.wi), 1e-4f * s.pdf);
        return s.wi;
      },
      [&](const Vec3& wi) { return bsdf.pdf(wo, wi); });
}

TEST(Materials, LeafSamplingChi2) {
  const Material leaf = make_leaf("leaf", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.5f));
  const auto r = chi2_bsdf(leaf, glm::normalize(Vec3(0.3f, -0.2f, 0.9f)), true, 21);
  EXPECT_GT(r.p_value, kMaterialAlpha) << "chi2 " << r.statistic;
  // From the back side (wo below the surface): transmission goes up.
  const auto r2 = chi2_bsdf(leaf, glm::normalize(Vec3(0.1f, 0.4f, -0.7f)), false, 22);
  EXPECT_GT(r2.p_value, kMaterialAlpha) << "chi2 " << r2.statistic;
}

TEST(Materials, DiffuseSamplingChi2) {
  const Material d = make_diffuse("d", DenseSpectrum::constant(0.6f));
  const auto r = chi2_bsdf(d, glm::normalize(Vec3(-0.5f, 0.1f, 0.4f)), true, 23);
  EXPECT_GT(r.p_value, kMaterialAlpha) << "chi2 " << r.statistic;
}

TEST(Materials, InterleavedLobesEqualTheMaterialsOwn) {
  // The render's MaterialLobes gives each material's own ρ and τ bit for bit, per face, at any
  // wavelength (grid points, between them, below the grid) — the lerp of the same grid values.
  DenseSpectrum rf, tf, rb, tb, soil;
  for (int i = 0; i < kLambdaSamples; ++i) {
    const float x = static_cast<float>(i) / kLambdaSamples;
    rf[i] = 0.05f + 0.4f * x * x;
    tf[i] = 0.5f * x;
    rb[i] = 0.1f + 0.3f * std::sin(9.0f * x) * std::sin(9.0f * x);
    tb[i] = 0.4f * (1.0f - x);
    soil[i] = 0.2f + 0.1f * std::cos(20.0f * x);
  }
  const std::vector<Material> materials = {make_diffuse("soil", soil), make_leaf("leaf", rf, tf, rb, tb)};
  const MaterialLobes table(materials);
  Pcg32 rng(25);
  int differ = 0;
  for (int n = 0; n < 20000; ++n) {
    SampledWavelengths wl;
    for (int k = 0; k < kLambdaCount; ++k)
      wl.lambda_nm[k] =
          n % 3 == 0 ? std::floor(kLambdaMin + rng.uniform() * 2198.0f) : 250.0f + 2248.0f * rng.uniform();
    for (uint32_t m = 0; m < materials.size(); ++m)
      for (bool front : {true, false}) {
        HitContext ctx;
        ctx.material = m;
        ctx.front = front;
        ctx.wl = &wl;
        const Bsdf own = bsdf_at(materials[m], wl, front), interleaved = table.bsdf(ctx);
        differ += own.reflectance() != interleaved.reflectance() || own.albedo() != interleaved.albedo() ||
                  own.lobe_count() != interleaved.lobe_count();
      }
  }
  EXPECT_EQ(differ, 0);
  // The faces are not swapped: the leaf's back reflectance differs from its front's.
  const SampledWavelengths wl = wl550();
  HitContext front, back;
  front.material = back.material = 1;
  front.wl = back.wl = &wl;
  back.front = false;
  EXPECT_NE(table.bsdf(front).reflectance(), table.bsdf(back).reflectance());
}

TEST(Materials, LeafEnergyIsReflectancePlusTransmittance) {
  const Material leaf = make_leaf("leaf", DenseSpectrum::constant(0.2f), DenseSpectrum::constant(0.45f),
                                  DenseSpectrum::constant(0.1f), DenseSpectrum::constant(0.45f));
  for (bool front : {true, false}) {
    const SampledWavelengths wl = wl550();
    const Bsdf bsdf = bsdf_at(leaf, wl, front);
    const Vec3 wo = glm::normalize(Vec3(0.2f, 0.3f, 0.8f));
    Pcg32 rng(24);
    double reflect = 0, transmit = 0;
    constexpr int n = 200000;
    for (int i = 0; i < n; ++i) {
      BsdfSample s;
      ASSERT_TRUE(bsdf.sample(wo, Vec2(rng.uniform(), rng.uniform()), rng.uniform(), &s));
      // The sample weight equals f·|cos|/pdf computed from eval and pdf.
      const float expect = bsdf.eval(wo, s.wi)[0] * std::abs(s.wi.z) / s.pdf;
      ASSERT_NEAR(s.value[0], expect, 1e-4f);
      (s.transmitted ? transmit : reflect) += s.value[0];
    }
    EXPECT_NEAR(reflect / n, front ? 0.2 : 0.1, 0.005);
    EXPECT_NEAR(transmit / n, 0.45, 0.005);
  }
}

TEST(Materials, RejectsNonPhysicalSpectra) {
  try {
    make_leaf("bad_leaf", DenseSpectrum::constant(0.6f), DenseSpectrum::constant(0.5f));
    FAIL() << "rho + tau > 1 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad_leaf"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("> 1"), std::string::npos);
  }
  EXPECT_THROW(make_diffuse("neg", DenseSpectrum::constant(-0.1f)), Error);
  EXPECT_THROW(make_diffuse("big", DenseSpectrum::constant(1.2f)), Error);
  EXPECT_NO_THROW(make_leaf("ok", DenseSpectrum::constant(0.5f), DenseSpectrum::constant(0.5f)));
}

TEST(Materials, EmissiveEmitsOnItsFacesAndReflectsDiffusely) {
  const Material lamp =
      make_emissive("lamp", DenseSpectrum::constant(2.0f), DenseSpectrum::constant(0.25f), /*two_sided=*/false);
  const Material both = make_emissive("both", DenseSpectrum::constant(2.0f), DenseSpectrum::constant(0.0f), true);
  const SampledWavelengths wl = wl550();
  HitContext ctx;
  ctx.wl = &wl;
  EXPECT_TRUE(emits(lamp));
  EXPECT_FALSE(emits(make_diffuse("d", DenseSpectrum::constant(0.5f))));
  EXPECT_EQ(emitted_radiance(lamp, ctx), SampledSpectrum(2.0f));
  EXPECT_EQ(emitted_radiance(both, ctx), SampledSpectrum(2.0f));
  ctx.front = false;
  EXPECT_EQ(emitted_radiance(lamp, ctx), SampledSpectrum(0.0f));
  EXPECT_EQ(emitted_radiance(both, ctx), SampledSpectrum(2.0f));
  EXPECT_EQ(material_bsdf(lamp, ctx).albedo(), SampledSpectrum(0.25f));
  const auto r = chi2_bsdf(lamp, glm::normalize(Vec3(0.2f, 0.1f, 0.6f)), true, 26);
  EXPECT_GT(r.p_value, kMaterialAlpha) << "chi2 " << r.statistic;
  EXPECT_THROW(make_emissive("neg", DenseSpectrum::constant(-1.0f), DenseSpectrum::constant(0.0f), false), Error);
  EXPECT_THROW(make_emissive("big", DenseSpectrum::constant(1.0f), DenseSpectrum::constant(1.5f), false), Error);
}

}  // namespace
}  // namespace sylva
