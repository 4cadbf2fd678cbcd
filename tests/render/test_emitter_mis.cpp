// Emitters sampled as lights with MIS (render/integrator.h, "Emission"; render/lights/emitters.h):
// a diffuse floor lit only by a small emissive rectangle against the closed-form form factor, the
// MIS, BSDF-only and light-only estimators against each other (also through haze and a turbid
// slab, where the shadow rays to emitters are finite segments), and MIS's variance against
// BSDF sampling's on the small emitter.

#include "geometry/primitives.h"
#include "geometry/solids/half_space.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace sylva {
namespace {

using EmitterStrategy = IntegratorSettings::EmitterSampling;

constexpr float kLampHeight = 1.0f, kLampX = 0.3f, kLampY = 0.2f;  // the lamp, m
constexpr float kLampLe = 2.0f, kLampFloorAlbedo = 0.5f;

// Point-to-parallel-rectangle form factor: a point under the corner of an a × b rectangle at
// height h (Howell's catalogue, C-11), summed over the four quarters of a centred one.
double centred_rectangle_form_factor(double a, double b, double h) {
  const double x = a / 2 / h, y = b / 2 / h;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return 4.0 * (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2.0 * kPi);
}

// A large diffuse floor (ρ 0.5) at z = 0 and, above its centre at height 1 m, a 0.3 × 0.2 m black
// one-sided emitter facing down (an instance of an upward plane turned over); no sun, no sky. The
// camera looks straight down at the floor's centre from below the lamp with a 1° field.
Scene lamp_test_scene() {
  Scene s;
  s.sun.enabled = false;
  s.sky.enabled = false;
  const uint32_t floor = s.add_material("floor", make_diffuse("floor", DenseSpectrum::constant(kLampFloorAlbedo)));
  const uint32_t lamp = s.add_material(
      "lamp", make_emissive("lamp", DenseSpectrum::constant(kLampLe), DenseSpectrum::constant(0.0f), false));
  s.instances.push_back(
      {s.add_prototype(Prototype{"floor", make_plane(40, 40), floor, {}, 0, {}, {}, {}, 0, {}, 0}), Mat4(1.0f), 0});
  const Mat4 turned = glm::rotate(glm::translate(Mat4(1.0f), Vec3(0, 0, kLampHeight)), kPi, Vec3(1, 0, 0));
  s.instances.push_back(
      {s.add_prototype(Prototype{"lamp", make_plane(kLampX, kLampY), lamp, {}, 0, {}, {}, {}, 0, {}, 0}), turned, 0});
  s.camera.position = {0, 0, 0.5f};
  s.camera.target = {0, 0, 0};
  s.camera.up = {0, 1, 0};
  std::get<PerspectiveProjection>(s.camera.projection).vfov_deg = 1;
  return s;
}

struct LampEstimate {
  double mean = 0, standard_error = 0, mean_variance = 0;  // mean_variance: a pixel's, per sample
};

// Every channel's mean over the image, its standard error, and the mean per-sample variance.
std::vector<LampEstimate> render_lamp_estimates(const Scene& scene, EmitterStrategy strategy, int spp) {
  RenderSettings settings = test::test_settings(32, 32, spp);
  settings.integrator.emitter_sampling = strategy;
  Renderer r(scene, settings);
  Film film = r.make_film();
  r.render(film);
  const Image img = r.make_image(film);
  std::vector<LampEstimate> out;
  for (const Band& b : test::test_bands())
    for (const std::string& channel : b.channels) {
      const int c = img.find_channel(channel), v = img.find_channel("var." + channel);
      double sum = 0, var = 0;
      const double n = static_cast<double>(img.width) * img.height;
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
          sum += img.at(x, y, c);
          var += img.at(x, y, v);
        }
      out.push_back({sum / n, std::sqrt(var) / n, var / n * spp});
    }
  return out;
}

std::vector<double> lamp_channel_integrals() {
  std::vector<double> out;
  for (const Band& b : test::test_bands())
    for (const DenseSpectrum& w : b.weights) out.push_back(w.integral());
  return out;
}

TEST(EmitterMis, FloorUnderASmallLampMatchesTheFormFactor) {
  // L = ρ · L_e · F: the floor's only light is the lamp's (black, so nothing comes back).
  const double f = centred_rectangle_form_factor(kLampX, kLampY, kLampHeight);
  const std::vector<double> w = lamp_channel_integrals();
  const Scene s = lamp_test_scene();
  const std::vector<LampEstimate> mis = render_lamp_estimates(s, EmitterStrategy::kMis, 16);
  const std::vector<LampEstimate> light = render_lamp_estimates(s, EmitterStrategy::kLight, 16);
  const std::vector<LampEstimate> bsdf = render_lamp_estimates(s, EmitterStrategy::kBsdf, 256);
  for (size_t c = 0; c < w.size(); ++c) {
    const double expected = kLampFloorAlbedo * kLampLe * f * w[c];
    for (const auto& [name, e] : {std::pair{"mis", mis[c]}, {"light", light[c]}, {"bsdf", bsdf[c]}}) {
      const double z = (e.mean - expected) / e.standard_error;
      std::printf("[emitter mis] channel %zu %-5s mean %.6g expected %.6g (%.2f s.e., s.e. %.2g%%)\n", c, name, e.mean,
                  expected, z, 100 * e.standard_error / expected);
      EXPECT_LT(std::abs(z), 4.0) << name << " channel " << c;
    }
    // The estimators against each other, each pair's difference within its combined error.
    const auto agree = [&](const LampEstimate& a, const LampEstimate& b, const char* what) {
      const double se = std::hypot(a.standard_error, b.standard_error);
      EXPECT_LT(std::abs(a.mean - b.mean), 4.0 * se) << what << " channel " << c;
    };
    agree(mis[c], light[c], "mis vs light");
    agree(mis[c], bsdf[c], "mis vs bsdf");
    // MIS takes the light samples where they are good: far less variance per sample than BSDF
    // sampling, which meets a lamp of 0.06 sr at 1 m about once in 50 bounces.
    const double ratio = bsdf[c].mean_variance / mis[c].mean_variance;
    std::printf("[emitter mis] channel %zu variance per sample: bsdf / mis = %.1f\n", c, ratio);
    EXPECT_GT(ratio, 10.0) << "channel " << c;
  }
}

TEST(EmitterMis, EstimatorsAgreeThroughHazeAndATurbidSlab) {
  // The same lamp, now a two-sided reflecting one (ρ 0.3), with a grey box beside it, in a
  // homogeneous haze, above a slab of grey turbid leaves the floor's light crosses: no closed form,
  // but the three estimators must agree (the light samples' shadow rays are finite segments that
  // start and end in the media).
  Scene s = lamp_test_scene();
  s.materials[1] = make_emissive("lamp", DenseSpectrum::constant(kLampLe), DenseSpectrum::constant(0.3f), true);
  s.haze.enabled = true;
  s.haze.extinction_550 = 0.3f;
  s.haze.top = 3.0f;
  const uint32_t leaf =
      s.add_material("leaf", make_leaf("leaf", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.3f)));
  HalfSpaceSolid slab;
  for (int axis = 0; axis < 3; ++axis)
    for (const float sign : {-1.0f, 1.0f}) {
      Vec3 n(0.0f);
      n[axis] = sign;
      slab.planes.push_back(HalfSpace{n, axis == 2 ? 0.15f : 3.0f});
    }
  slab.leaf_area_density = 1.5f;
  finish_solid(slab);
  Prototype p;
  p.solids = {slab};
  p.solid_palettes = {{leaf}};
  s.instances.push_back({s.add_prototype(p), glm::translate(Mat4(1.0f), Vec3(0, 0, 0.35f)), 0});
  s.instances.push_back({s.add_prototype(Prototype{"box", make_box(Vec3(0.3f)), 0, {}, 0, {}, {}, {}, 0, {}, 0}),
                         glm::translate(Mat4(1.0f), Vec3(0.4f, 0, 0)), 0});
  s.camera.position = {0, -1.2f, 0.8f};
  s.camera.target = {0, 0, 0.2f};
  std::get<PerspectiveProjection>(s.camera.projection).vfov_deg = 40;
  const std::vector<LampEstimate> mis = render_lamp_estimates(s, EmitterStrategy::kMis, 32);
  const std::vector<LampEstimate> light = render_lamp_estimates(s, EmitterStrategy::kLight, 32);
  const std::vector<LampEstimate> bsdf = render_lamp_estimates(s, EmitterStrategy::kBsdf, 512);
  for (size_t c = 0; c < mis.size(); ++c) {
    std::printf("[emitter mis] media channel %zu: mis %.5g ± %.2g, light %.5g ± %.2g, bsdf %.5g ± %.2g\n", c,
                mis[c].mean, mis[c].standard_error, light[c].mean, light[c].standard_error, bsdf[c].mean,
                bsdf[c].standard_error);
    EXPECT_GT(mis[c].mean, 0.0);
    EXPECT_LT(std::abs(mis[c].mean - light[c].mean), 4.0 * std::hypot(mis[c].standard_error, light[c].standard_error))
        << "mis vs light, channel " << c;
    EXPECT_LT(std::abs(mis[c].mean - bsdf[c].mean), 4.0 * std::hypot(mis[c].standard_error, bsdf[c].standard_error))
        << "mis vs bsdf, channel " << c;
  }
}

}  // namespace
}  // namespace sylva
