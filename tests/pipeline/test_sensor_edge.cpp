// A slanted edge rendered by Sylva and sensed (issue 44): two coplanar Lambertian half-planes
// (reflectance 0.2 and 0.8) under a uniform sky, seen from straight above by an orthographic
// camera, with the edge at 5° to the image's columns. The render's pixels are area means (box
// filter), so after the sensor's optics and detector integration the ISO 12233-style measurement
// (tests/support/slanted_edge.h, the edge fitted to the image) recovers the implemented MTF
// (`system_otf`) at a quarter of the sampling frequency and at Nyquist within 5 %. Each half's
// radiance is a constant (0.2 and 0.8 of the sky's); the Monte Carlo error of the measurement
// (wavelengths, the hemisphere, the pixel coverage at the edge) is bounded by a second seed.

#include "core/band.h"
#include "pipeline/render_call.h"
#include "pipeline/sensor_stage.h"
#include "sensor/sensor.h"
#include "tests/support/slanted_edge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace sylva {
namespace {

// Each half-plane is 20 m × 40 m, rotated 5° about z and moved by ±10 m along its rotated x axis,
// so the two meet on the line through the origin at 5° to the y axis.
constexpr const char* kEdgeSceneToml = R"([render]
width = 256
height = 256
spp = 128
bands = ["rgb"]
max_depth = 2

[camera]
type = "orthographic"
position = [0.0, 0.0, 10.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
width = 12.8

[sun]
enabled = false

[sky]
model = "uniform"

[materials.dark]
reflectance = 0.2

[materials.bright]
reflectance = 0.8

[[meshes]]
shape = "plane"
size = [20, 40]
material = "dark"
rotate = [0, 0, 5]
translate = [-9.961946980917455, -0.8715574274765817, 0.0]

[[meshes]]
shape = "plane"
size = [20, 40]
material = "bright"
rotate = [0, 0, 5]
translate = [9.961946980917455, 0.8715574274765817, 0.0]

[sensor]
oversample = 4
)";

RenderResult render_edge(uint64_t seed) {
  RenderCallOptions o;
  o.request.source = SceneSource::from_text(kEdgeSceneToml, "edge scene");
  o.request.threads = 2;
  o.request.seed = static_cast<int64_t>(seed);
  RenderObserver quiet;
  return render_scene(o, quiet);
}

// The measured MTF at `f` cycles per pitch of a sensed plane (width × height detectors) and the
// edge's unit normal, for the implemented OTF at the same frequency along it.
struct EdgeMeasurement {
  double mtf = 0, normal_u = 0, normal_v = 0;
};

EdgeMeasurement measure_rendered_edge(const std::vector<float>& plane, int width, int height, double f) {
  constexpr int kMargin = 6;  // rows at the top and bottom: the mirrored border of the blur
  const test::EdgeLine line = test::fit_edge_line(plane, width, kMargin, height - kMargin);
  std::vector<test::EdgeSample> samples;
  for (int j = kMargin; j < height - kMargin; ++j)
    for (int i = 0; i < width; ++i)
      samples.push_back({line.distance(i + 0.5, j + 0.5), plane[static_cast<size_t>(j) * width + i]});
  int empty = 0;
  EdgeMeasurement m;
  m.mtf = test::edge_mtf(samples, f, &empty);
  EXPECT_EQ(empty, 0) << "empty bins: the edge is not slanted enough (fitted slope " << line.b << ")";
  EXPECT_NEAR(std::atan(std::abs(line.b)) * 180 / 3.14159265358979323846, 5.0, 0.2) << "the fitted edge";
  m.normal_u = line.normal_u();
  m.normal_v = line.normal_v();
  return m;
}

std::vector<float> channel_plane(const Image& image, const std::string& name) {
  const int c = image.find_channel(name);
  EXPECT_GE(c, 0) << name;
  std::vector<float> plane(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) plane[static_cast<size_t>(y) * image.width + x] = image.at(x, y, c);
  return plane;
}

TEST(SensorRenderedEdge, RecoversTheImplementedMtfAtNyquist) {
  const RenderResult first = render_edge(1), second = render_edge(2);
  ASSERT_EQ(first.status, RenderStatus::finished);
  const Band rgb = resolve_band("rgb");
  const SensorChannel green = describe_channel("G", "rgb", rgb.weights[1]);
  SensorParams sharp;  // the scene's [sensor]: f/2.8, no defocus or jitter, 4 render pixels per pitch
  sharp.sampling.oversample = 4;
  SensorParams soft = sharp;
  soft.optics.f_number = 4.0;
  soft.optics.obscuration = 0.35;
  soft.optics.defocus_px = 0.3;
  soft.optics.jitter_rms_px = 0.2;
  for (const SensorParams* p : {&sharp, &soft}) {
    // The sharp case is the render call's own sensor stage; the soft one the sensor on its image.
    const auto sensed = [&](const RenderResult& r) {
      return p == &sharp ? r.sensor : apply_sensor(r.image, {green}, *p, {}, 1).image;
    };
    const Image a = sensed(first), b = sensed(second);
    ASSERT_EQ(a.width, 64);
    const std::vector<float> plane_a = channel_plane(a, "optical.G"), plane_b = channel_plane(b, "optical.G");
    for (double f : {0.25, 0.5}) {
      const EdgeMeasurement m = measure_rendered_edge(plane_a, a.width, a.height, f);
      const EdgeMeasurement other = measure_rendered_edge(plane_b, b.width, b.height, f);
      const double implemented = system_otf(p->optics, p->sampling.pitch_um, green, f * m.normal_u, f * m.normal_v);
      // Two seeds: their mean against the implemented MTF, their spread bounding the Monte Carlo
      // error of that mean (noise also biases a measured MTF upwards, hence 128 samples a pixel).
      const double mean = 0.5 * (m.mtf + other.mtf), standard_error = 0.5 * std::abs(m.mtf - other.mtf);
      EXPECT_NEAR(mean / implemented, 1.0, 0.05)
          << "f/" << p->optics.f_number << " at " << f << " cycles/pitch: measured " << m.mtf << " and " << other.mtf
          << ", implemented " << implemented;
      EXPECT_LT(standard_error / implemented, 0.01) << "seeds 1 and 2 at " << f << ": " << m.mtf << ", " << other.mtf;
    }
  }
}

}  // namespace
}  // namespace sylva
