// Light transport: white furnaces per band (rgb and nir), emitters (an emissive enclosure, a quad
// seen directly, emitters in a sky furnace), the sun-lit Lambertian plane against its closed form, determinism across
// thread counts, and interrupted + resumed renders.

#include "core/error.h"
#include "geometry/primitives.h"
#include "geometry/trees/fournier_grindal/fournier_grindal.h"
#include "render/materials/leaf_medium.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <thread>

namespace sylva {
namespace {

using test::same_bits;
using test::small_forest_scene;
using test::test_bands;
using test::test_settings;

Scene furnace_scene() {
  Scene s;
  s.sun.enabled = false;
  s.sky.model = UniformSky{};
  s.sky.spectrum = DenseSpectrum::constant(1.0f);
  s.camera.position = {0, -6, 0.5f};
  s.camera.target = {0, 0, 0.5f};
  std::get<PerspectiveProjection>(s.camera.projection).vfov_deg = 30;
  return s;
}

struct ChannelStats {
  double mean = 0, standard_error = 0;
};

// The mean over all pixels of a channel and its standard error from the per-pixel variances.
ChannelStats pixel_mean(const Image& img, const std::string& channel) {
  const int c = img.find_channel(channel), v = img.find_channel("var." + channel);
  EXPECT_GE(c, 0);
  EXPECT_GE(v, 0);
  double sum = 0, var = 0;
  const double n = static_cast<double>(img.width) * img.height;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      sum += img.at(x, y, c);
      var += img.at(x, y, v);
    }
  return {sum / n, std::sqrt(var) / n};
}

Image render_image(const Scene& scene, int w, int h, int spp, int threads = 0, int max_depth = 64) {
  RenderSettings settings = test_settings(w, h, spp, max_depth);
  settings.threads = threads;
  Renderer r(scene, settings);
  Film film = r.make_film();
  r.render(film);
  return r.make_image(film);
}

// Every channel's pixel mean equals `expected(weight)` within 4.5 standard errors and 1%.
void expect_channels(const Image& img, const std::function<double(const DenseSpectrum&)>& expected, const char* what) {
  for (const Band& b : test_bands())
    for (size_t c = 0; c < b.channels.size(); ++c) {
      const ChannelStats s = pixel_mean(img, b.channels[c]);
      const double e = expected(b.weights[c]);
      EXPECT_LT(std::abs(s.mean - e), 4.5 * s.standard_error + 1e-7)
          << what << " " << b.channels[c] << ": " << s.mean << " vs " << e << " ± " << s.standard_error;
      EXPECT_LT(std::abs(s.mean - e), 0.01 * std::abs(e)) << what << " " << b.channels[c];
      std::printf("[transport] %-16s %-6s mean %.6g expected %.6g rel.err %+.3f%% (%.1f s.e.)\n", what,
                  b.channels[c].c_str(), s.mean, e, 100.0 * (s.mean - e) / e, (s.mean - e) / s.standard_error);
    }
}

double band_value_of_constant(const DenseSpectrum& w) { return w.integral(); }

TEST(Transport, WhiteFurnaceLeafCloud) {
  // Leaves with ρ + τ = 1 (alpha-cut ovals, many bounces) under a uniform unit sky: radiance 1.
  Scene s = furnace_scene();
  const uint32_t m =
      s.add_material("leaf", make_leaf("leaf", DenseSpectrum::constant(0.4f), DenseSpectrum::constant(0.6f)));
  s.instances.push_back(
      {s.add_prototype(test::leaf_cloud_prototype(m, 4000, 3)), glm::translate(Mat4(1.0f), Vec3(0, 0, 0.5f)), 0});
  const Image img = render_image(s, 24, 24, 64);
  expect_channels(img, band_value_of_constant, "leaf furnace");
}

TEST(Transport, WhiteFurnaceClosedLambertianObjects) {
  // A closed box and a sphere of albedo 1 (instanced, scaled) under a uniform unit sky: radiance 1.
  Scene s = furnace_scene();
  const uint32_t m = s.add_material("white", make_diffuse("white", DenseSpectrum::constant(1.0f)));
  Prototype box{"box", make_box(Vec3(1.0f)), m, {}, 0, {}, {}, {}, 0, {}, 0};
  Prototype sphere{"sphere", make_sphere(0.5f, 32), m, {}, 0, {}, {}, {}, 0, {}, 0};
  s.instances.push_back({s.add_prototype(box), glm::translate(Mat4(1.0f), Vec3(-0.6f, 0, 0)), 0});
  s.instances.push_back(
      {s.add_prototype(sphere), glm::scale(glm::translate(Mat4(1.0f), Vec3(0.7f, 0, 0.5f)), Vec3(1.3f)), 0});
  const Image img = render_image(s, 24, 24, 64);
  expect_channels(img, band_value_of_constant, "closed furnace");
}

// A small six-plane crown on a trunk, fBm-displaced: the furnace tests' half-space tree.
FournierGrindalParams furnace_crown() {
  FournierGrindalParams fg;
  fg.normals = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1.2f}, {0, 0, -0.8f}};
  fg.displacement_m = 0.15f;
  fg.fbm.wavelength_m = 0.5f;
  fg.crown_base_m = 0.5f;
  fg.trunk_radius_m = 0.08f;
  fg.trunk_top_radius_m = 0.05f;
  return fg;
}

TEST(Transport, WhiteFurnaceHalfSpaceSolids) {
  // A Fournier–Grindal crown (fBm-displaced, sphere-traced) and its trunk, albedo 1, instanced and
  // scaled, under a uniform unit sky: radiance 1 (the user geometry's normals and self-hits agree).
  Scene s = furnace_scene();
  const uint32_t m = s.add_material("white", make_diffuse("white", DenseSpectrum::constant(1.0f)));
  FournierGrindalParams fg = furnace_crown();
  Prototype p;
  p.solids = make_fournier_grindal_tree(fg, 4).solids;
  p.solid_palettes.assign(p.solids.size(), {m});
  s.instances.push_back({s.add_prototype(p), glm::scale(glm::translate(Mat4(1.0f), Vec3(0, 0, -0.6f)), Vec3(0.8f)), 0});
  const Image img = render_image(s, 24, 24, 64);
  expect_channels(img, band_value_of_constant, "half-space furnace");
}

TEST(Transport, WhiteFurnaceTurbidCrown) {
  // A volumetric Fournier–Grindal crown (fBm-displaced boundary) of leaves with ρ + τ = 1 around an
  // albedo-1 trunk, under a uniform unit sky: radiance 1 (free flight, the leaf phase function's
  // sampling and evaluation, and Beer's-law shadow rays agree).
  Scene s = furnace_scene();
  const uint32_t white = s.add_material("white", make_diffuse("white", DenseSpectrum::constant(1.0f)));
  const uint32_t leaf =
      s.add_material("leaf", make_leaf("leaf", DenseSpectrum::constant(0.45f), DenseSpectrum::constant(0.55f)));
  FournierGrindalParams fg = furnace_crown();
  fg.leaf_area_density = 3.0f;
  Prototype p;
  p.solids = make_fournier_grindal_tree(fg, 4).solids;
  for (const HalfSpaceSolid& solid : p.solids) p.solid_palettes.push_back({solid.material_slot == 0 ? white : leaf});
  s.instances.push_back({s.add_prototype(p), glm::scale(glm::translate(Mat4(1.0f), Vec3(0, 0, -0.6f)), Vec3(0.8f)), 0});
  const Image img = render_image(s, 24, 24, 64);
  expect_channels(img, band_value_of_constant, "turbid crown furnace");
}

// A scene without lights: no sun, no sky.
Scene dark_scene() {
  Scene s = furnace_scene();
  s.sky.enabled = false;
  return s;
}

TEST(Transport, EmissiveEnclosureIsLeOverOneMinusAlbedo) {
  // Inside a closed box whose walls emit L_e = 0.3 from both faces and reflect ρ = 0.6 diffusely,
  // every ray sees L = L_e Σ ρ^k = L_e/(1 − ρ) = 0.75 (the emission counted at camera and BSDF hits).
  Scene s = dark_scene();
  const uint32_t m =
      s.add_material("wall", make_emissive("wall", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.6f), true));
  s.instances.push_back(
      {s.add_prototype(Prototype{"box", make_box(Vec3(4.0f)), m, {}, 0, {}, {}, {}, 0, {}, 0}), Mat4(1.0f), 0});
  s.camera.position = {0.3f, -1.2f, 1.5f};
  s.camera.target = {0, 1, 2.2f};
  std::get<PerspectiveProjection>(s.camera.projection).vfov_deg = 70;
  const Image img = render_image(s, 24, 24, 64);
  expect_channels(
      img, [](const DenseSpectrum& w) { return 0.3 / (1.0 - 0.6) * w.integral(); }, "emissive enclosure");
}

TEST(Transport, EmissiveQuadSeenDirectlyIsLe) {
  // A black emitter filling the view in a dark scene: every pixel's expectation is its L_e(λ)
  // weighted by the channel (the carried wavelengths are the only randomness); from behind, a
  // one-sided emitter is exactly black and a two-sided one the same as in front.
  DenseSpectrum le;
  for (int i = 0; i < kLambdaSamples; ++i) le[i] = 0.5f + 1.5f * static_cast<float>(i) / kLambdaSamples;
  for (const bool two_sided : {false, true})
    for (const float side : {1.0f, -1.0f}) {
      Scene s = dark_scene();
      const uint32_t m = s.add_material("lamp", make_emissive("lamp", le, DenseSpectrum::constant(0.0f), two_sided));
      s.instances.push_back(
          {s.add_prototype(Prototype{"quad", make_plane(20, 20), m, {}, 0, {}, {}, {}, 0, {}, 0}), Mat4(1.0f), 0});
      s.camera.position = {0.2f, -0.3f, 2.0f * side};
      s.camera.target = {0, 0, 0};
      const Image img = render_image(s, 32, 32, 64);
      if (two_sided || side > 0) {
        expect_channels(
            img, [&](const DenseSpectrum& w) { return (le * w).integral(); }, "emissive quad");
      } else {
        for (const Band& b : test_bands())
          for (const std::string& channel : b.channels) EXPECT_EQ(pixel_mean(img, channel).mean, 0.0) << channel;
      }
    }
}

TEST(Transport, EmittersInAUniformSkyFurnace) {
  // A closed box and a sphere that reflect ρ = 0.7 and emit L_e = 1 − ρ under a uniform unit sky:
  // L = L_e + ρ · 1 = 1 everywhere. The sky's light reaches them by light samples and BSDF samples
  // (MIS) while their emission counts at hits: the two must not double-count or miss each other.
  Scene s = furnace_scene();
  const uint32_t m = s.add_material(
      "grey", make_emissive("grey", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.7f), false));
  Prototype box{"box", make_box(Vec3(1.0f)), m, {}, 0, {}, {}, {}, 0, {}, 0};
  Prototype sphere{"sphere", make_sphere(0.5f, 32), m, {}, 0, {}, {}, {}, 0, {}, 0};
  s.instances.push_back({s.add_prototype(box), glm::translate(Mat4(1.0f), Vec3(-0.6f, 0, 0)), 0});
  s.instances.push_back(
      {s.add_prototype(sphere), glm::scale(glm::translate(Mat4(1.0f), Vec3(0.7f, 0, 0.5f)), Vec3(1.3f)), 0});
  const Image img = render_image(s, 24, 24, 64);
  expect_channels(img, band_value_of_constant, "emitter sky furnace");
}

TEST(Transport, TurbidSlabTransmitsBeersLaw) {
  // Black leaves (ρ = τ = 0) in a slab 1 m thick, LAD 1.2, between the camera and a uniform unit
  // sky: every pixel sees exp(−G·LAD·1 m) = exp(−0.6) (the camera's 2° field changes the path by
  // < 0.02 %).
  Scene s = furnace_scene();
  s.camera.position = {0, -6, 0};
  s.camera.target = {0, 0, 0};
  std::get<PerspectiveProjection>(s.camera.projection).vfov_deg = 2;
  const uint32_t black =
      s.add_material("black", make_leaf("black", DenseSpectrum::constant(0.0f), DenseSpectrum::constant(0.0f)));
  HalfSpaceSolid slab;
  for (int axis = 0; axis < 3; ++axis)
    for (const float sign : {-1.0f, 1.0f}) {
      Vec3 n(0.0f);
      n[axis] = sign;
      slab.planes.push_back(HalfSpace{n, axis == 1 ? 0.5f : 50.0f});
    }
  slab.leaf_area_density = 1.2f;
  finish_solid(slab);
  Prototype p;
  p.solids = {slab};
  p.solid_palettes = {{black}};
  s.instances.push_back({s.add_prototype(p), Mat4(1.0f), 0});
  const Image img = render_image(s, 16, 16, 1024);
  const double expected = std::exp(-kSphericalG * 1.2);
  expect_channels(
      img, [&](const DenseSpectrum& w) { return expected * w.integral(); }, "turbid slab");
}

TEST(Transport, HazeTransmitsBeerLambertPerWavelength) {
  // An absorbing haze layer (ω = 0, Ångström α = 1.3) 10 m thick above a camera looking at the
  // zenith of a uniform unit sky: each band sees ∫ w(λ) exp(−σ_550 (λ/550)^−α · 10 m) dλ (the 2°
  // field lengthens the path by < 0.02 %). Exercises the wavelengths' MIS weights inside the integrator.
  Scene s = furnace_scene();
  s.camera.position = {0, 0, 0};
  s.camera.target = {0, 0, 1};
  s.camera.up = {0, 1, 0};
  std::get<PerspectiveProjection>(s.camera.projection).vfov_deg = 2;
  s.haze.enabled = true;
  s.haze.extinction_550 = 0.06f;
  s.haze.angstrom = 1.3f;
  s.haze.albedo = 0.0f;
  s.haze.top = 10.0f;
  const Image img = render_image(s, 16, 16, 256);
  expect_channels(
      img,
      [&](const DenseSpectrum& w) {
        DenseSpectrum t;
        for (int i = 0; i < kLambdaSamples; ++i)
          t[i] = std::exp(-0.06f * 10.0f * std::pow(DenseSpectrum::grid_lambda(i) / 550.0f, -1.3f));
        return (t * w).integral();
      },
      "absorbing haze");
}

TEST(Transport, WhiteFurnaceConservativeHaze) {
  // Conservative haze (ω = 1, spectral extinction) around the camera, a white sphere and a white
  // ground, under a uniform unit sky: every path ends in the sky, so the radiance is 1 in every
  // band. Homogeneous below a top and exponential. (The ground closes the medium from below: in an
  // unbounded conservative half-space a random walk's escape time has no finite mean, and the
  // safety cap on the path length would bias any renderer's estimate.)
  for (const HazeProfile profile : {HazeProfile::Homogeneous, HazeProfile::Exponential}) {
    Scene s = furnace_scene();
    const uint32_t white = s.add_material("white", make_diffuse("white", DenseSpectrum::constant(1.0f)));
    s.instances.push_back(
        {s.add_prototype(Prototype{"ball", make_sphere(1.0f, 24), white, {}, 0, {}, {}, {}, 0, {}, 0}),
         glm::translate(Mat4(1.0f), Vec3(0, 0, 1.2f)), 0});
    s.instances.push_back(
        {s.add_prototype(Prototype{"ground", make_plane(2000, 2000), white, {}, 0, {}, {}, {}, 0, {}, 0}), Mat4(1.0f),
         0});
    s.haze.enabled = true;
    s.haze.profile = profile;
    s.haze.extinction_550 = 0.15f;
    s.haze.angstrom = 1.3f;
    s.haze.albedo = 1.0f;
    s.haze.g = 0.6f;
    s.haze.scale_height = 4.0f;
    s.haze.top = profile == HazeProfile::Homogeneous ? 6.0f : std::numeric_limits<float>::infinity();
    const Image img = render_image(s, 24, 24, 256, 0, 1024);
    expect_channels(img, band_value_of_constant,
                    profile == HazeProfile::Homogeneous ? "homogeneous haze furnace" : "exponential haze furnace");
  }
}

TEST(Transport, SunLitLambertianPlaneMatchesClosedForm) {
  // L = ρ E cos θ / π per band, with spectral ρ(λ) and the ASTM G173 direct spectrum.
  for (float elevation : {30.0f, 65.0f}) {
    Scene s;
    s.sky.enabled = false;
    s.sun.elevation_deg = elevation;
    s.sun.azimuth_deg = 100;
    s.camera.position = {0, 0, 4};
    s.camera.target = {0, 0, 0};
    s.camera.up = {0, 1, 0};
    std::get<PerspectiveProjection>(s.camera.projection).vfov_deg = 40;
    std::vector<double> l = {300, 500, 700, 900, 2500}, v = {0.1, 0.2, 0.5, 0.6, 0.3};
    const DenseSpectrum rho = DenseSpectrum::from_samples(l, v, Extrapolate::Clamp);
    const uint32_t m = s.add_material("soil", make_diffuse("soil", rho));
    s.instances.push_back(
        {s.add_prototype(Prototype{"ground", make_plane(1000, 1000), m, {}, 0, {}, {}, {}, 0, {}, 0}), Mat4(1.0f), 0});
    const Image img = render_image(s, 16, 16, 256, 0, 4);
    const double cos_theta = std::sin(radians(elevation));
    expect_channels(
        img, [&](const DenseSpectrum& w) { return (rho * s.sun.irradiance * w).integral() * cos_theta / M_PI; },
        "sun-lit plane");
  }
}

TEST(Transport, GroundBelowTheHorizonLightsAPlaneFromBelow) {
  // The underside of a large plane sees only the lower hemisphere: L = ρ L_ground per band, with
  // L_ground = a/π (E_sun sin(elevation) + E_sky).
  Scene s;
  s.sun.elevation_deg = 50;
  s.sky.ground_albedo = 0.25f;
  s.camera.position = {0, 0, 0};
  s.camera.target = {0, 0, 1};
  s.camera.up = {0, 1, 0};
  std::get<PerspectiveProjection>(s.camera.projection).vfov_deg = 40;
  const uint32_t m = s.add_material("white", make_diffuse("white", DenseSpectrum::constant(0.8f)));
  const Mat4 flip = glm::rotate(glm::translate(Mat4(1.0f), Vec3(0, 0, 2)), kPi, Vec3(1, 0, 0));
  s.instances.push_back(
      {s.add_prototype(Prototype{"ceiling", make_plane(2000, 2000), m, {}, 0, {}, {}, {}, 0, {}, 0}), flip, 0});
  const Image img = render_image(s, 16, 16, 256, 0, 4);
  DenseSpectrum ground = s.sky.spectrum;
  for (int i = 0; i < kLambdaSamples; ++i) ground[i] += s.sun.irradiance[i] * std::sin(radians(50.0f));
  ground *= 0.25f * kInvPi;
  expect_channels(
      img, [&](const DenseSpectrum& w) { return 0.8 * (ground * w).integral(); }, "ground-lit");
}

TEST(Transport, BitIdenticalAtAnyThreadCount) {
  const Scene s = small_forest_scene();
  const Image one = render_image(s, 40, 24, 6, 1, 8);
  const Image two = render_image(s, 40, 24, 6, 2, 8);
  const Image four = render_image(s, 40, 24, 6, 4, 8);
  EXPECT_TRUE(same_bits(one, two));
  EXPECT_TRUE(same_bits(one, four));
  // And the image is not trivially constant.
  const ChannelStats st = pixel_mean(one, "G");
  EXPECT_GT(st.mean, 0.0);
}

TEST(Transport, InterruptedAndResumedEqualsUninterrupted) {
  const Scene s = small_forest_scene();
  const RenderSettings settings = test_settings(48, 32, 16, 8);
  Renderer full(s, settings);
  Film reference = full.make_film();
  full.render(reference);
  const Image expected = full.make_image(reference);

  // Stop asynchronously mid-render, checkpoint to disk, resume in a fresh renderer.
  std::atomic<bool> cancel{false};
  RenderSettings interrupted = settings;
  interrupted.cancel = &cancel;
  interrupted.threads = 2;
  Renderer first(s, interrupted);
  Film film = first.make_film();
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    cancel = true;
  });
  const RenderStats st = first.render(film);
  stopper.join();
  const auto checkpoint = std::filesystem::temp_directory_path() / "sylva_test_resume.checkpoint";
  film.save(checkpoint, "key-1");
  EXPECT_THROW(Film::load(checkpoint, "another render"), Error);
  Film resumed = Film::load(checkpoint, "key-1");
  std::filesystem::remove(checkpoint);
  EXPECT_EQ(resumed.total_samples(), film.total_samples());
  Renderer second(s, settings);
  second.render(resumed);
  EXPECT_EQ(resumed.total_samples(), reference.total_samples());
  EXPECT_TRUE(same_bits(second.make_image(resumed), expected)) << "interrupted: " << st.interrupted;
}

TEST(Transport, MoreSamplesLaterContinueTheSameSequence) {
  // 8 spp then topped up to 16 equals 16 at once (progressive refinement of a finished render).
  const Scene s = small_forest_scene();
  RenderSettings settings = test_settings(20, 12, 8);
  Renderer r8(s, settings);
  Film film = r8.make_film();
  r8.render(film);
  settings.spp = 16;
  Renderer r16(s, settings);
  r16.render(film);
  Film direct = r16.make_film();
  r16.render(direct);
  EXPECT_TRUE(same_bits(r16.make_image(film), r16.make_image(direct)));
}

}  // namespace
}  // namespace sylva
