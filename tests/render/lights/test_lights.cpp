// Sun and sky: χ² of the mixture sampler against its pdf, normalisation, CIE luminance.

#include "core/band.h"
#include "core/error.h"
#include "core/rng.h"
#include "render/lights/lights.h"
#include "tests/support/chi2_directions.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

const double kAlpha = sidak_alpha(0.01, 7);  // seven χ² tests in this file

Chi2Result chi2_environment(const Environment& env, uint64_t seed) {
  Pcg32 rng(seed);
  SampledWavelengths wl;
  return test::chi2_directions(
      {},
      [&](int) {
        const LightSample s = env.sample(Vec2(rng.uniform(), rng.uniform()), rng.uniform(), wl);
        EXPECT_NEAR(s.pdf, env.pdf(s.wi), 1e-3f * s.pdf);
        return s.pdf > 0 ? s.wi : Vec3(0.0f);
      },
      [&](const Vec3& d) { return env.pdf(d); });
}

TEST(Lights, CieSkyChi2) {
  SunDesc sun;
  sun.enabled = false;
  sun.azimuth_deg = 200;
  sun.elevation_deg = 30;
  SkyDesc sky;
  const auto r = chi2_environment(Environment(sun, sky), 11);
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic << " dof " << r.dof;
}

TEST(Lights, UniformSkyChi2) {
  SunDesc sun;
  sun.enabled = false;
  SkyDesc sky;
  sky.model = UniformSky{};
  sky.spectrum = DenseSpectrum::constant(1.0f);
  const auto r = chi2_environment(Environment(sun, sky), 12);
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
}

TEST(Lights, CieSkyWithGroundChi2AndRadiance) {
  SunDesc sun;
  sun.elevation_deg = 40;
  SkyDesc sky;
  sky.ground_albedo = 0.3f;
  // χ² over the whole sphere with the sun off (the ground is lit by it all the same).
  SunDesc no_sun = sun;
  no_sun.enabled = false;
  const auto r = chi2_environment(Environment(no_sun, sky), 17);
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
  // Below the horizon: L = a/π (E_sun sin(elevation) + E_sky).
  const Environment env(sun, sky);
  SampledWavelengths wl;
  wl.lambda_nm = SampledSpectrum(600.0f);
  const float expected =
      0.3f / kPi * (sun.irradiance.eval(600.0f) * std::sin(radians(40.0f)) + sky.spectrum.eval(600.0f));
  EXPECT_NEAR(env.eval(glm::normalize(Vec3(0.3f, 0.2f, -0.5f)), wl)[0], expected, 1e-5f * expected);
  // A ground needs the CIE sky.
  SkyDesc uniform;
  uniform.model = UniformSky{};
  uniform.ground_albedo = 0.2f;
  EXPECT_THROW(Environment(sun, uniform), Error);
}

TEST(Lights, SunAndSkyMixtureChi2) {
  // The real 0.27° sun: samples in the disc form one bin (expected: the sun's share plus the sky's
  // tiny mass there); all others are histogrammed against the sky part of the mixture pdf.
  SunDesc sun;
  sun.elevation_deg = 50;
  SkyDesc sky;
  const Environment env(sun, sky);
  const double p_sun = env.sun_selection_probability();
  ASSERT_GT(p_sun, 0.0);
  ASSERT_LT(p_sun, 1.0);
  const double sun_pdf = p_sun * uniform_cone_pdf(env.sun_one_minus_cos());
  Pcg32 rng(13);
  SampledWavelengths wl;
  const auto r = test::chi2_directions(
      {},
      [&](int) {
        const LightSample s = env.sample(Vec2(rng.uniform(), rng.uniform()), rng.uniform(), wl);
        EXPECT_NEAR(s.pdf, env.pdf(s.wi), 1e-3f * s.pdf);
        return env.in_sun(s.wi) ? Vec3(0.0f) : s.wi;
      },
      [&](const Vec3& d) { return env.pdf(d) - (env.in_sun(d) ? sun_pdf : 0.0); });
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
}

TEST(Lights, SunConeChi2InTheSunsFrame) {
  // Equal-area bins in ((1 − cos θ)/(1 − cos α), φ) about the solar axis: uniform if correct.
  SunDesc sun;
  sun.elevation_deg = 20;
  sun.azimuth_deg = 250;
  SkyDesc sky;
  sky.enabled = false;
  const Environment env(sun, sky);
  const Frame f = env.sun_frame();
  Pcg32 rng(16);
  SampledWavelengths wl;
  constexpr int n = 1'000'000, nr = 20, np = 40;
  std::vector<double> obs(nr * np, 0.0), exp(nr * np, double(n) / (nr * np));
  for (int i = 0; i < n; ++i) {
    const LightSample s = env.sample(Vec2(rng.uniform(), rng.uniform()), rng.uniform(), wl);
    ASSERT_TRUE(env.in_sun(s.wi));
    const Vec3 l = f.to_local(s.wi);
    const float omc = 0.5f * glm::dot(s.wi - f.z, s.wi - f.z);  // 1 − cos θ, precisely
    float phi = std::atan2(l.y, l.x);
    if (phi < 0) phi += kTwoPi;
    const int a = std::min(nr - 1, int(omc / env.sun_one_minus_cos() * nr));
    const int b = std::min(np - 1, int(phi / kTwoPi * np));
    obs[a * np + b] += 1;
  }
  const auto r = chi2_test(obs, exp);
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic;
}

TEST(Lights, SkyTableLeavesTheSolarDiscToTheSun) {
  // The sky's table is empty wherever the solar disc reaches, so a sun sample's density is the
  // sun's alone, exactly as pdf() finds it — for a sun across φ = 0 (due east), at and near the
  // zenith (every column of the top rows), at the horizon, with a ground, and the largest disc.
  struct Case {
    float azimuth, elevation, radius, ground;
  };
  for (const Case c : {Case{90, 30, 0.2665f, 0}, Case{89.99f, 45, 0.2665f, 0}, Case{0, 89.9f, 0.2665f, 0},
                       Case{200, 90, 0.2665f, 0}, Case{135, 0.1f, 0.2665f, 0.3f}, Case{300, 20, 9.9f, 0.2f}}) {
    SCOPED_TRACE(::testing::Message() << "sun at " << c.azimuth << "°, " << c.elevation << "°");
    SunDesc sun;
    sun.azimuth_deg = c.azimuth;
    sun.elevation_deg = c.elevation;
    sun.angular_radius_deg = c.radius;
    SkyDesc sky;
    sky.ground_albedo = c.ground;
    const Environment env(sun, sky);
    const float sun_pdf = env.sun_selection_probability() * uniform_cone_pdf(env.sun_one_minus_cos());
    Pcg32 rng(21);
    SampledWavelengths wl;
    int mismatches = 0;
    for (int i = 0; i < 200'000; ++i) {
      const LightSample s = env.sample(Vec2(rng.uniform(), rng.uniform()), 0.0f, wl);
      ASSERT_TRUE(env.in_sun(s.wi));
      mismatches += s.pdf != sun_pdf || env.pdf(s.wi) != sun_pdf;
    }
    EXPECT_EQ(mismatches, 0);
    // The sky still has the rest of the sphere: a sky sample is never in the disc.
    for (int i = 0; i < 200'000; ++i)
      mismatches += env.in_sun(env.sample(Vec2(rng.uniform(), rng.uniform()), 1.0f, wl).wi);
    EXPECT_EQ(mismatches, 0);
  }
}

TEST(Lights, SolarDiscSamplesAndIrradiance) {
  SunDesc sun;
  sun.elevation_deg = 35;
  SkyDesc sky;
  sky.enabled = false;
  const Environment env(sun, sky);
  const Vec3 axis = sun_direction(sun.azimuth_deg, sun.elevation_deg);
  Pcg32 rng(14);
  SampledWavelengths wl;
  wl.lambda_nm = SampledSpectrum(550.0f);
  // Irradiance on a surface facing the sun, estimated by sampling: E = E[L cos / pdf].
  double e = 0;
  constexpr int n = 100000;
  for (int i = 0; i < n; ++i) {
    const LightSample s = env.sample(Vec2(rng.uniform(), rng.uniform()), rng.uniform(), wl);
    ASSERT_TRUE(env.in_sun(s.wi));
    ASSERT_GT(s.pdf, 0.0f);
    e += s.radiance[0] * glm::dot(s.wi, axis) / s.pdf;
  }
  EXPECT_NEAR(e / n, sun.irradiance.eval(550.0f), 1e-3 * sun.irradiance.eval(550.0f));
}

TEST(Lights, SkyHorizontalIrradianceMatchesItsSpectrum) {
  SunDesc sun;
  sun.enabled = false;
  sun.elevation_deg = 40;
  for (int type : {1, 5, 12, 15}) {
    SkyDesc sky;
    CieSky cie;
    cie.type = type;
    sky.model = cie;
    const Environment env(sun, sky);
    SampledWavelengths wl;
    wl.lambda_nm = SampledSpectrum(500.0f);
    // ∫ L cos θ dω over the upper hemisphere by a fine midpoint rule.
    double e = 0;
    constexpr int nt = 400, np = 800;
    for (int j = 0; j < nt; ++j)
      for (int i = 0; i < np; ++i) {
        const double theta = (j + 0.5) * M_PI / 2 / nt, phi = (i + 0.5) * 2 * M_PI / np;
        const Vec3 d = spherical_direction(float(std::sin(theta)), float(std::cos(theta)), float(phi));
        e += env.eval_sky(d, wl)[0] * std::cos(theta) * std::sin(theta) * (M_PI / 2 / nt) * (2 * M_PI / np);
      }
    EXPECT_NEAR(e, sky.spectrum.eval(500.0f), 0.01 * sky.spectrum.eval(500.0f)) << "CIE type " << type;
  }
}

TEST(Lights, CieRelativeLuminance) {
  const Vec3 sun = sun_direction(180, 45);
  // Zenith is the reference (1) for every type; type 5 is uniform everywhere above the horizon.
  for (int type = 1; type <= 15; ++type) EXPECT_NEAR(cie_sky_relative_luminance(type, {0, 0, 1}, sun), 1.0f, 1e-5f);
  EXPECT_NEAR(cie_sky_relative_luminance(5, glm::normalize(Vec3(1, 1, 0.2f)), sun), 1.0f, 1e-5f);
  EXPECT_EQ(cie_sky_relative_luminance(12, {0, 0, -1}, sun), 0.0f);
  // Clear sky (12): brighter near the sun than opposite it at the same elevation.
  const Vec3 near_sun = sun_direction(180, 30), away = sun_direction(0, 30);
  EXPECT_GT(cie_sky_relative_luminance(12, near_sun, sun), 2.0f * cie_sky_relative_luminance(12, away, sun));
  // Overcast (1): three times brighter at the zenith than at the horizon (Moon & Spencer).
  EXPECT_NEAR(cie_sky_relative_luminance(1, glm::normalize(Vec3(1, 0, 1e-3f)), sun), 1.0f / 3.0f, 0.01f);
}

// A CieSky prepared for the scene's sun keeps what depends on the sun only and gives the same bits
// as the one-direction function; for another sun it computes afresh.
TEST(Lights, CiePreparedShapeMatchesTheFunction) {
  const Vec3 sun = sun_direction(140, 35), other = sun_direction(20, 60);
  CieSky sky;
  sky.type = 12;
  sky.prepare(sun);
  Pcg32 rng(7);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 d = glm::normalize(symmetric3(rng));
    EXPECT_EQ(sky.relative_radiance(d, sun), cie_sky_relative_luminance(12, d, sun));
    EXPECT_EQ(sky.relative_radiance(d, other), cie_sky_relative_luminance(12, d, other));
  }
}

// The Preetham sky (render/lights/preetham_sky.h): sampled by its luminance map, evaluated
// spectrally; χ² at a high and a low sun.
TEST(Lights, PreethamSkyChi2) {
  for (const float elevation : {50.0f, 4.0f}) {
    SunDesc sun;
    sun.enabled = false;
    sun.azimuth_deg = 120;
    sun.elevation_deg = elevation;
    SkyDesc sky;
    sky.model = PreethamSky{};
    const auto r = chi2_environment(Environment(sun, sky), 21 + static_cast<uint64_t>(elevation));
    EXPECT_GT(r.p_value, kAlpha) << "sun elevation " << elevation << " chi2 " << r.statistic << " dof " << r.dof;
  }
}

// ∫ L(ω, λ) cos θ dω over the upper hemisphere at one wavelength, by a fine midpoint rule.
double horizontal_from_radiance(const Environment& env, float lambda_nm) {
  SampledWavelengths wl;
  wl.lambda_nm = SampledSpectrum(lambda_nm);
  double e = 0;
  constexpr int nt = 300, np = 600;
  for (int j = 0; j < nt; ++j)
    for (int i = 0; i < np; ++i) {
      const double theta = (j + 0.5) * M_PI / 2 / nt, phi = (i + 0.5) * 2 * M_PI / np;
      const Vec3 d = spherical_direction(float(std::sin(theta)), float(std::cos(theta)), float(phi));
      e += env.eval_sky(d, wl)[0] * std::cos(theta) * std::sin(theta) * (M_PI / 2 / nt) * (2 * M_PI / np);
    }
  return e;
}

TEST(Lights, PreethamHorizontalIrradianceMatchesItsSpectrum) {
  SunDesc sun;
  sun.enabled = false;
  for (const float elevation : {60.0f, 25.0f, 5.0f}) {
    sun.elevation_deg = elevation;
    // A stated spectrum: matched at every wavelength, visible and near infrared.
    SkyDesc stated;
    stated.model = PreethamSky{3.0f, false};
    const Environment env(sun, stated);
    for (const float lambda : {350.0f, 450.0f, 550.0f, 680.0f, 865.0f, 1250.0f, 1650.0f, 2200.0f}) {
      const double expected = stated.spectrum.eval(lambda);
      EXPECT_NEAR(horizontal_from_radiance(env, lambda), expected, 0.01 * expected)
          << "elevation " << elevation << " λ " << lambda;
      EXPECT_NEAR(env.horizontal_irradiance().eval(lambda), expected, 1e-4 * expected);
    }
    // Its own spectrum: the 300–2500 nm total equals ASTM G173 diffuse's, and the radiance
    // integrates to the reported horizontal irradiance at every wavelength.
    SkyDesc own;
    own.model = PreethamSky{3.0f, true};
    const Environment env_own(sun, own);
    const DenseSpectrum e = env_own.horizontal_irradiance();
    EXPECT_NEAR(e.integral(), own.spectrum.integral(), 1e-4 * own.spectrum.integral());
    for (const float lambda : {450.0f, 650.0f, 1050.0f})
      EXPECT_NEAR(horizontal_from_radiance(env_own, lambda), e.eval(lambda), 0.01 * e.eval(lambda));
  }
}

// Linear Rec.709 R, G, B of the sky radiance in direction `d` through the renderer's rgb band.
Vec3 sky_rgb(const Environment& env, const Vec3& d) {
  static const Band rgb = make_rgb_band();
  Vec3 c(0.0f);
  for (int i = 0; i < kLambdaSamples; i += 2) {
    SampledWavelengths wl;
    wl.lambda_nm = SampledSpectrum(DenseSpectrum::grid_lambda(i));
    const float l = env.eval_sky(d, wl)[0];
    for (int k = 0; k < 3; ++k) c[k] += 2.0f * l * rgb.weights[static_cast<size_t>(k)][i];
  }
  return c;
}

TEST(Lights, PreethamSkyIsBlueOverheadWhiterAtTheHorizonAndWarmAtLowSun) {
  SunDesc sun;
  sun.enabled = false;
  sun.azimuth_deg = 180;
  SkyDesc sky;
  sky.model = PreethamSky{};
  const Vec3 zenith(0, 0, 1), north_horizon = glm::normalize(Vec3(0, 1, 0.05f));
  sun.elevation_deg = 45;
  const Environment high(sun, sky);
  const Vec3 z = sky_rgb(high, zenith), h = sky_rgb(high, north_horizon);
  std::printf("[sky] sun 45°: zenith rgb %.4f %.4f %.4f (B/R %.2f), horizon opposite the sun B/R %.2f\n", z.x, z.y, z.z,
              z.z / z.x, h.z / h.x);
  EXPECT_GT(z.z, 1.3f * z.x) << "the zenith must be blue";
  EXPECT_GT(z.z, z.y);
  EXPECT_LT(h.z / h.x, z.z / z.x) << "the horizon must be whiter than the zenith";
  // The sky beside a low sun is redder than beside a high one.
  const Vec3 near_high = sky_rgb(high, sun_direction(180, 45 + 10));
  sun.elevation_deg = 3;
  const Environment low(sun, sky);
  const Vec3 near_low = sky_rgb(low, sun_direction(180, 3 + 10));
  std::printf("[sky] beside the sun B/R: sun at 45° %.2f, sun at 3° %.2f\n", near_high.z / near_high.x,
              near_low.z / near_low.x);
  EXPECT_LT(near_low.z / near_low.x, 0.8f * near_high.z / near_high.x);
}

TEST(Lights, PreethamChromaticityMatchesThePaper) {
  // Preetham et al. 1999, Appendix A.2 by hand at T = 2, θs = 30°: the zenith chromaticity.
  const float ts = radians(30.0f), t = 2.0f;
  const float xz = t * t * (0.00166f * ts * ts * ts - 0.00375f * ts * ts + 0.00209f * ts) +
                   t * (-0.02903f * ts * ts * ts + 0.06377f * ts * ts - 0.03202f * ts + 0.00394f) +
                   (0.11693f * ts * ts * ts - 0.21196f * ts * ts + 0.06052f * ts + 0.25886f);
  const Vec3 xyY = preetham_xyY(t, Vec3(0, 0, 1), sun_direction(0, 60));
  EXPECT_NEAR(xyY.x, xz, 1e-5f);
  EXPECT_NEAR(xyY.z, 1.0f, 1e-5f);
  EXPECT_GT(xyY.x, 0.2f);
  EXPECT_LT(xyY.x, 0.3f);
  // Below the horizon nothing.
  EXPECT_EQ(preetham_xyY(t, glm::normalize(Vec3(1, 0, -0.1f)), sun_direction(0, 60)), Vec3(0.0f));
}

}  // namespace
}  // namespace sylva
