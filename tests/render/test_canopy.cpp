// Disc canopies, cyclic plots and the plot sensor (docs/radiometry.md): Beer's law through a layer
// of uniformly oriented discs, energy closure over a black soil, a conservative canopy over white
// soil reflecting everything, the cyclic boundary losing no energy, and the orthographic camera and
// the plot sensor agreeing on a flat plot.

#include "core/error.h"
#include "geometry/leaf_discs.h"
#include "geometry/primitives.h"
#include "render/renderer.h"
#include "render/sensors/orthographic.h"
#include "render/sensors/plot_sensor.h"
#include "tests/render/render_test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace sylva {
namespace {

struct CanopySpec {
  float lai = 2;
  LeafAngles angles = LeafAngles::spherical;
  float sun_zenith_deg = 20;
  float leaf_rho = 0.0f, leaf_tau = 0.0f, soil_rho = 0.0f;
  float size = 10;  // plot side, m
  float disc_radius = 0.05f;
  bool cyclic = true;
};

// A square plot with a soil plane of its size and a homogeneous disc layer 2 m high, under a
// collimated sun only.
Scene canopy_scene(const CanopySpec& c) {
  Scene s;
  s.sun.elevation_deg = 90 - c.sun_zenith_deg;
  s.sun.azimuth_deg = 180;
  s.sun.angular_radius_deg = 1e-3f;
  s.sky.enabled = false;
  const uint32_t soil = s.add_material("soil", make_diffuse("soil", DenseSpectrum::constant(c.soil_rho)));
  const uint32_t leaf = s.add_material(
      "leaf", make_leaf("leaf", DenseSpectrum::constant(c.leaf_rho), DenseSpectrum::constant(c.leaf_tau)));
  Prototype ground;
  ground.name = "soil";
  ground.triangles = make_plane(c.size, c.size);
  ground.triangle_material = soil;
  s.instances.push_back({s.add_prototype(std::move(ground)), Mat4(1.0f), 0});
  Prototype canopy;
  canopy.name = "canopy";
  canopy.discs =
      make_homogeneous_layer(Vec2(-0.5f * c.size), Vec2(0.5f * c.size), 2.0f, c.lai, c.disc_radius, c.angles, 11);
  canopy.disc_material = leaf;
  s.instances.push_back({s.add_prototype(std::move(canopy)), Mat4(1.0f), 0});
  s.plot.defined = true;
  s.plot.lo = Vec2(-0.5f * c.size);
  s.plot.hi = Vec2(0.5f * c.size);
  s.plot.cyclic = c.cyclic;
  return s;
}

MeasureSettings flux_settings(int samples) {
  MeasureSettings m;
  m.bands = {resolve_band("S2A_B8")};
  m.plot.flux_samples = samples;
  m.plot.ground_materials = {0};
  m.threads = 2;
  return m;
}

enum Term { kLeaves, kBark, kGround, kGroundDirect, kGroundTotal, kReflected, kClosure };

// Direct transmittance of a layer of uniformly (spherically) oriented discs: exp(−0.5·LAI/cos θ).
// Besides the Monte Carlo error, one realisation of N random discs covers the plot by a random
// amount: the relative spread of the unshadowed fraction is about sqrt(λ a / A) (λ = 0.5 LAI/cos θ,
// a = a disc's shadow, A = the plot), the "finite-size" error added to the tolerance.
TEST(Canopy, DirectTransmittanceFollowsBeersLaw) {
  for (const float zenith : {0.0f, 30.0f, 50.0f, 65.0f}) {
    CanopySpec c;
    c.lai = 2;
    c.sun_zenith_deg = zenith;
    c.size = 20;
    const Scene scene = canopy_scene(c);
    const EmbreeScene embree(scene);
    const FluxTable t = measure_flux(scene, embree, flux_settings(40000));
    const double mu = std::cos(radians(zenith));
    const double lambda = 0.5 * c.lai / mu;
    const double expected = std::exp(-lambda);
    const double shadow = kPi * c.disc_radius * c.disc_radius * 0.5 / mu;  // mean projected disc area / cos θ
    const double finite = expected * std::sqrt(lambda * shadow / (c.size * c.size));
    const double got = t.mean[0][kGroundDirect], se = t.se[0][kGroundDirect];
    std::printf("[canopy] Beer sun zenith %2.0f: T = %.5f ± %.5f (finite size ± %.5f), exp(-0.5 LAI/mu) = %.5f\n",
                zenith, got, se, finite, expected);
    EXPECT_LT(std::abs(got - expected), 4 * std::sqrt(se * se + finite * finite)) << "sun zenith " << zenith;
    // Black leaves and soil: everything that is not transmitted is absorbed by the leaves.
    EXPECT_NEAR(t.mean[0][kLeaves] + t.mean[0][kGround], 1.0, 1e-9);
  }
}

// Over a black soil on a cyclic plot light is absorbed or reflected: the budget closes to 1. Without
// the cyclic boundary light escapes through the plot's sides and the budget does not close — the
// check that the closure test can fail and that the cyclic boundary is what keeps the energy.
TEST(Canopy, BlackSoilBudgetClosesOnlyOnACyclicPlot) {
  CanopySpec c;
  c.lai = 3;
  c.leaf_rho = 0.4957f;
  c.leaf_tau = 0.4409f;
  c.angles = LeafAngles::erectophile;
  c.sun_zenith_deg = 30;
  c.size = 6;
  const Scene cyclic = canopy_scene(c);
  const EmbreeScene embree(cyclic);
  const FluxTable t = measure_flux(cyclic, embree, flux_settings(40000));
  const auto& m = t.mean[0];
  const auto& se = t.se[0];
  std::printf("[canopy] black soil, cyclic: leaves %.4f ground %.4f reflected %.4f sum %.5f ± %.5f\n", m[kLeaves],
              m[kGround], m[kReflected], m[kClosure], se[kClosure]);
  EXPECT_LT(std::abs(m[kClosure] - 1.0), 4 * se[kClosure]);
  EXPECT_GT(se[kClosure], 0.0);
  EXPECT_LT(se[kClosure], 0.01);
  EXPECT_EQ(m[kBark], 0.0);
  EXPECT_NEAR(m[kGround], m[kGroundTotal], 1e-9);  // black soil absorbs all that reaches it
  c.cyclic = false;
  const Scene open = canopy_scene(c);
  const EmbreeScene open_embree(open);
  const FluxTable o = measure_flux(open, open_embree, flux_settings(40000));
  std::printf("[canopy] black soil, open plot: sum %.5f ± %.5f\n", o.mean[0][kClosure], o.se[0][kClosure]);
  EXPECT_GT(1.0 - o.mean[0][kClosure], 10 * o.se[0][kClosure]);
}

// ρ + τ = 1 leaves over a white soil absorb nothing: a cyclic plot reflects all the incident light.
TEST(Canopy, ConservativeCanopyOverWhiteSoilReflectsEverything) {
  CanopySpec c;
  c.lai = 2;
  c.leaf_rho = 0.6f;
  c.leaf_tau = 0.4f;
  c.soil_rho = 1.0f;
  c.size = 6;
  const Scene scene = canopy_scene(c);
  const EmbreeScene embree(scene);
  const FluxTable t = measure_flux(scene, embree, flux_settings(20000));
  std::printf("[canopy] conservative: reflected %.5f ± %.5f, absorbed %.2g\n", t.mean[0][kReflected],
              t.se[0][kReflected], t.mean[0][kLeaves] + t.mean[0][kGround]);
  EXPECT_LT(std::abs(t.mean[0][kReflected] - 1.0), 4 * t.se[0][kReflected]);
  EXPECT_EQ(t.mean[0][kLeaves] + t.mean[0][kGround], 0.0);
  // The BRF's hemispherical mean is the albedo: 1. A few views of the BRF all lie near 1 too (a
  // conservative canopy over white soil is not Lambertian, so only loosely).
  MeasureSettings m = flux_settings(1);
  m.plot.samples = 4000;
  m.plot.views = principal_plane_views(-60, 60, 60, scene.sun.azimuth_deg);
  const BrfTable b = measure_brf(scene, embree, m);
  for (size_t v = 0; v < b.views.size(); ++v) EXPECT_NEAR(b.mean[v][0], 1.0, 0.25) << b.views[v].label_deg;
}

// A flat plot of two Lambertian halves (ρ 0.2 and 0.6) under sun and sky: the orthographic camera
// looking straight down with the plot as its footprint and the plot sensor at nadir measure the
// same reflectance factor, 0.4, within their errors.
TEST(Canopy, OrthographicCameraAndPlotSensorAgreeOnAFlatPlot) {
  Scene s;
  s.sun.elevation_deg = 50;
  s.sun.azimuth_deg = 150;
  const uint32_t dark = s.add_material("dark", make_diffuse("dark", DenseSpectrum::constant(0.2f)));
  const uint32_t bright = s.add_material("bright", make_diffuse("bright", DenseSpectrum::constant(0.6f)));
  for (int half = 0; half < 2; ++half) {
    Prototype p;
    p.name = half ? "bright" : "dark";
    p.triangles = make_plane(4, 8);
    p.triangle_material = half ? bright : dark;
    s.instances.push_back({s.add_prototype(std::move(p)), glm::translate(Mat4(1.0f), Vec3(half ? 2 : -2, 0, 0)), 0});
  }
  s.plot.defined = true;
  s.plot.lo = Vec2(-4);
  s.plot.hi = Vec2(4);
  s.camera.position = {0, 0, 10};
  s.camera.target = {0, 0, 0};
  s.camera.up = {0, 1, 0};
  OrthographicProjection ortho;
  ortho.width_m = 8;
  s.camera.projection = ortho;
  RenderSettings rs = test::test_settings(16, 16, 32);
  rs.bands = {resolve_band("S2A_B4"), resolve_band("S2A_B8")};
  rs.quantity = Quantity::reflectance;
  Renderer r(s, rs);
  Film film = r.make_film();
  r.render(film);
  const Image img = r.make_image(film);
  MeasureSettings m;
  m.bands = rs.bands;
  m.plot.samples = 8192;
  m.plot.views = {PlotView{0, 0, 0}};
  m.threads = 2;
  const BrfTable b = measure_brf(s, r.embree(), m);
  for (size_t c = 0; c < b.channels.size(); ++c) {
    const int ch = img.find_channel(b.channels[c]), var = img.find_channel("var." + b.channels[c]);
    double sum = 0, v = 0;
    const double n = static_cast<double>(img.width) * img.height;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        sum += img.at(x, y, ch);
        v += img.at(x, y, var);
      }
    const double camera = sum / n, camera_se = std::sqrt(v) / n;
    std::printf("[canopy] flat plot %s: camera %.5f ± %.5f, plot sensor %.5f ± %.5f\n", b.channels[c].c_str(), camera,
                camera_se, b.mean[0][c], b.se[0][c]);
    EXPECT_LT(std::abs(camera - b.mean[0][c]), 4 * std::hypot(camera_se, b.se[0][c]));
    EXPECT_LT(std::abs(b.mean[0][c] - 0.4), 4 * b.se[0][c]);
  }
}

// A cyclic plot is a periodic world: the same canopy shifted by a whole period (content outside the
// cell) measures the same BRF. The same random numbers drive both, so only the few paths that
// rounding sends another way differ: far less than the standard error.
TEST(Canopy, CyclicPlotIsPeriodic) {
  CanopySpec c;
  c.leaf_rho = 0.45f;
  c.leaf_tau = 0.45f;
  c.soil_rho = 0.2f;
  c.size = 4;
  Scene a = canopy_scene(c);
  Scene b = canopy_scene(c);
  b.instances[1].world_from_object = glm::translate(Mat4(1.0f), Vec3(c.size, -c.size, 0));
  MeasureSettings m = flux_settings(1);
  m.plot.samples = 4000;
  m.plot.views = {PlotView{35, 90, 35}};
  const EmbreeScene ea(a), eb(b);
  const BrfTable ta = measure_brf(a, ea, m), tb = measure_brf(b, eb, m);
  EXPECT_NEAR(ta.mean[0][0], tb.mean[0][0], 0.25 * ta.se[0][0]);
  EXPECT_GT(ta.mean[0][0], 0.05);
}

TEST(Canopy, PlotSensorIsBitIdenticalAtAnyThreadCount) {
  CanopySpec c;
  c.leaf_rho = 0.45f;
  c.leaf_tau = 0.45f;
  c.soil_rho = 0.2f;
  c.size = 4;
  const Scene s = canopy_scene(c);
  const EmbreeScene e(s);
  MeasureSettings m = flux_settings(3000);
  m.plot.samples = 1000;
  m.plot.views = principal_plane_views(-40, 40, 40, 180);
  m.threads = 1;
  const BrfTable one = measure_brf(s, e, m);
  const FluxTable f1 = measure_flux(s, e, m);
  m.threads = 2;
  const BrfTable two = measure_brf(s, e, m);
  const FluxTable f2 = measure_flux(s, e, m);
  EXPECT_EQ(one.mean, two.mean);
  EXPECT_EQ(one.se, two.se);
  EXPECT_EQ(f1.mean, f2.mean);
}

TEST(Canopy, PrincipalPlaneViewsAreSignedBySunSide) {
  const std::vector<PlotView> v = principal_plane_views(-75, 75, 2, 150);
  ASSERT_EQ(v.size(), 76u);
  EXPECT_FLOAT_EQ(v.front().label_deg, -75);
  EXPECT_FLOAT_EQ(v.front().zenith_deg, 75);
  EXPECT_FLOAT_EQ(v.front().azimuth_deg, 150);  // negative: looking from the sun's side
  EXPECT_FLOAT_EQ(v.back().azimuth_deg, 330);
  EXPECT_THROW(principal_plane_views(10, -10, 2, 0), Error);
  Scene no_plot;
  const EmbreeScene e(no_plot);
  MeasureSettings m = flux_settings(10);
  m.plot.views = v;
  EXPECT_THROW(measure_brf(no_plot, e, m), Error);
}

}  // namespace
}  // namespace sylva
