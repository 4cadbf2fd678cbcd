// Radiometric quantities (docs/radiometry.md): the horizontal irradiance of the sun and sky, and
// the reflectance factor a Lambertian panel reads in every band.

#include "core/error.h"
#include "geometry/primitives.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace sylva {
namespace {

std::vector<Band> radiometry_bands() {
  return {resolve_band("rgb"),    resolve_band("nir"),     resolve_band("red_edge"), resolve_band("S2A_B4"),
          resolve_band("S2A_B8"), resolve_band("S2A_B12"), resolve_band("L8_B5")};
}

// A large horizontal Lambertian panel of reflectance `rho` under the default sun and CIE sky,
// seen from above.
Scene panel_scene(const DenseSpectrum& rho, float sun_elevation_deg) {
  Scene s;
  s.sun.elevation_deg = sun_elevation_deg;
  s.sun.azimuth_deg = 200;
  s.camera.position = {0, 0, 4};
  s.camera.target = {0, 0, 0};
  s.camera.up = {0, 1, 0};
  std::get<PerspectiveProjection>(s.camera.projection).vfov_deg = 30;
  const uint32_t m = s.add_material("panel", make_diffuse("panel", rho));
  s.instances.push_back(
      {s.add_prototype(Prototype{"panel", make_plane(1000, 1000), m, {}, 0, {}, {}, {}, 0, {}, 0}), Mat4(1.0f), 0});
  return s;
}

Image render_reflectance(const Scene& scene, int spp, int light_samples = 1) {
  RenderSettings settings = test::test_settings(12, 12, spp, 4);
  settings.integrator.light_samples = light_samples;
  settings.bands = radiometry_bands();
  settings.quantity = Quantity::reflectance;
  Renderer r(scene, settings);
  Film film = r.make_film();
  r.render(film);
  return r.make_image(film);
}

// Mean of a channel over the image and its standard error from the per-pixel variances.
std::pair<double, double> image_mean(const Image& img, const std::string& channel) {
  const int c = img.find_channel(channel), v = img.find_channel("var." + channel);
  double sum = 0, var = 0;
  const double n = static_cast<double>(img.width) * img.height;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      sum += img.at(x, y, c);
      var += img.at(x, y, v);
    }
  return {sum / n, std::sqrt(var) / n};
}

TEST(Radiometry, HorizontalIrradianceIsSunCosinePlusDiffuse) {
  // CIE sky: normalised so its horizontal irradiance is the stated diffuse spectrum.
  SunDesc sun;
  sun.elevation_deg = 30;
  SkyDesc sky;
  const DenseSpectrum e = Environment(sun, sky).horizontal_irradiance();
  for (int i = 0; i < kLambdaSamples; i += 50) {
    const double expected = sky.spectrum[i] + sun.irradiance[i] * 0.5;
    EXPECT_NEAR(e[i], expected, 1e-4 * expected + 1e-7) << "lambda index " << i;
  }
  // Uniform sky of radiance L: π L on a horizontal plane (table quadrature, 1e-4).
  sun.enabled = false;
  sky.model = UniformSky{};
  sky.spectrum = DenseSpectrum::constant(2.0f);
  const DenseSpectrum u = Environment(sun, sky).horizontal_irradiance();
  EXPECT_NEAR(u[100], 2.0 * kPi, 2e-4 * 2.0 * kPi);
  // A sun below the horizon adds nothing.
  sun.enabled = true;
  sun.elevation_deg = -5;
  sky.enabled = false;
  EXPECT_EQ(Environment(sun, sky).horizontal_irradiance().max_value(), 0.0f);
}

TEST(Radiometry, LambertianPanelReadsItsOwnReflectanceInEveryBand) {
  // Constant ρ: every channel's reflectance factor is ρ. Spectral ρ(λ): the band's
  // irradiance-weighted mean, ∫ ρ E w / ∫ E w, with E = E_sun sin(elevation) + E_diffuse written
  // out here independently of Environment::horizontal_irradiance.
  std::vector<double> l = {300, 500, 680, 750, 1300, 2500}, v = {0.05, 0.08, 0.06, 0.45, 0.4, 0.15};
  const DenseSpectrum vegetation = DenseSpectrum::from_samples(l, v, Extrapolate::Clamp);
  for (float elevation : {25.0f, 60.0f})
    for (const DenseSpectrum& rho : {DenseSpectrum::constant(0.35f), vegetation}) {
      const Scene scene = panel_scene(rho, elevation);
      const Image img = render_reflectance(scene, 128);
      DenseSpectrum e = scene.sky.spectrum;
      for (int i = 0; i < kLambdaSamples; ++i) e[i] += scene.sun.irradiance[i] * std::sin(radians(elevation));
      for (const Band& b : radiometry_bands())
        for (size_t c = 0; c < b.channels.size(); ++c) {
          const double expected = (rho * e * b.weights[c]).integral() / (e * b.weights[c]).integral();
          const auto [mean, se] = image_mean(img, b.channels[c]);
          EXPECT_LT(std::abs(mean - expected), 4.5 * se + 1e-6)
              << b.channels[c] << ": " << mean << " vs " << expected << " ± " << se;
          std::printf("[radiometry] elevation %2.0f %-10s reflectance %.5f expected %.5f (%+.1f s.e.)\n", elevation,
                      b.channels[c].c_str(), mean, expected, (mean - expected) / se);
        }
    }
}

// Inside a conservative leaf cloud (ρ + τ = 1) under a uniform unit sky the radiance is 1 in every
// direction, however many bounces light takes to get in: the mean over the image and its standard
// error for `max_depth`.
std::pair<double, double> furnace_inside_cloud(int max_depth, int light_samples = 1, int spp = 32) {
  Scene s;
  s.sun.enabled = false;
  s.sky.model = UniformSky{};
  s.sky.spectrum = DenseSpectrum::constant(1.0f);
  s.camera.position = {0, 0, 0};
  s.camera.target = {1, 0, 0};
  const uint32_t m =
      s.add_material("leaf", make_leaf("leaf", DenseSpectrum::constant(0.55f), DenseSpectrum::constant(0.45f)));
  s.instances.push_back({s.add_prototype(test::leaf_cloud_prototype(m, 2500, 7)), Mat4(1.0f), 0});
  RenderSettings settings = test::test_settings(16, 16, spp, max_depth);
  settings.integrator.light_samples = light_samples;
  settings.bands = {resolve_band("nir")};
  Renderer r(s, settings);
  Film film = r.make_film();
  r.render(film);
  return image_mean(r.make_image(film), "nir.Y");
}

TEST(Radiometry, DefaultPathLengthIsUnbiasedInAConservativeCanopy) {
  // Russian roulette ends the paths; the default cap (IntegratorSettings) never matters here,
  // while a cap of 16 bounces loses the light that needs more.
  const auto [mean, se] = furnace_inside_cloud(IntegratorSettings{}.max_depth);
  std::printf("[radiometry] furnace inside a canopy, default depth %d: %.5f ± %.5f\n", IntegratorSettings{}.max_depth,
              mean, se);
  EXPECT_LT(std::abs(mean - 1.0), 4.5 * se);
  const auto [mean16, se16] = furnace_inside_cloud(16);
  std::printf("[radiometry] furnace inside a canopy, depth 16: %.5f ± %.5f\n", mean16, se16);
  EXPECT_LT(mean16, 1.0 - 4.5 * se16);
}

TEST(Radiometry, ReflectanceNeedsIrradiance) {
  Scene s = panel_scene(DenseSpectrum::constant(0.5f), 30);
  s.sun.enabled = false;
  s.sky.enabled = false;
  RenderSettings settings = test::test_settings(4, 4, 1, 4);
  settings.quantity = Quantity::reflectance;
  EXPECT_THROW(Renderer(s, settings), Error);
  EXPECT_EQ(parse_quantity("reflectance"), Quantity::reflectance);
  EXPECT_THROW(parse_quantity("brf"), Error);
}

// Several sun and sky samples at the first vertex (IntegratorSettings::light_samples), combined
// with the BSDF sample by the power heuristic on n·p_light: a wrong count in either weight biases
// the sum of the two estimators (by 2–4 % here, 6–10 standard errors at 256 spp).
TEST(Radiometry, SeveralLightSamplesStayUnbiasedInAConservativeCanopy) {
  for (const int n : {2, 3, 8}) {
    const auto [mean, se] = furnace_inside_cloud(IntegratorSettings{}.max_depth, n, 256);
    std::printf("[radiometry] furnace inside a canopy, %d light samples: %.5f ± %.5f\n", n, mean, se);
    EXPECT_LT(std::abs(mean - 1.0), 4.5 * se) << n << " light samples";
  }
}

TEST(Radiometry, SeveralLightSamplesKeepAPanelsReflectance) {
  // The sun is a small cone that the light samples find and the BSDF samples rarely do; the sky
  // is found by both.
  const Scene scene = panel_scene(DenseSpectrum::constant(0.35f), 40.0f);
  const Image img = render_reflectance(scene, 32, 4);
  for (const char* channel : {"R", "G", "B", "nir.Y", "S2A_B12.Y"}) {
    const auto [mean, se] = image_mean(img, channel);
    EXPECT_LT(std::abs(mean - 0.35), 4.5 * se + 1e-6) << channel << ": " << mean << " ± " << se;
  }
}

}  // namespace
}  // namespace sylva
