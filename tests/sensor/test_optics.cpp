// The optics and the sampling of the sensor model: the obscured aperture's OTF against the
// autocorrelation of an annulus, energy kept by the blur, the detector integration, and a
// slanted-edge measurement of the sensed edge against the implemented MTF at Nyquist.
#include "core/error.h"
#include "sensor/blur.h"
#include "sensor/otf.h"
#include "sensor/resample.h"
#include "sensor/sensor.h"
#include "tests/support/slanted_edge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <utility>
#include <vector>

namespace sylva {
namespace {

// The overlap of an annulus (outer radius 1, inner eta) with itself shifted by s, over its area,
// by the midpoint rule on a 1200² grid: the OTF at ν = s / 2.
double annulus_autocorrelation(double eta, double s) {
  constexpr int n = 1200;
  const double h = 2.0 / n;
  long inside = 0, overlap = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -1 + (i + 0.5) * h, y = -1 + (j + 0.5) * h;
      const double r0 = x * x + y * y, r1 = (x - s) * (x - s) + y * y;
      const bool a = r0 <= 1 && r0 >= eta * eta, b = r1 <= 1 && r1 >= eta * eta;
      inside += a;
      overlap += a && b;
    }
  return static_cast<double>(overlap) / static_cast<double>(inside);
}

TEST(SensorOtf, ObscuredApertureMatchesTheAnnulusAutocorrelation) {
  for (double eta : {0.0, 0.3, 0.5}) {
    EXPECT_NEAR(obscured_aperture_otf(0.0, eta), 1.0, 1e-12) << eta;
    for (double nu : {0.1, 0.2, 0.35, 0.5, 0.7, 0.9})
      EXPECT_NEAR(obscured_aperture_otf(nu, eta), annulus_autocorrelation(eta, 2 * nu), 4e-3)
          << "eta " << eta << " nu " << nu;
    EXPECT_EQ(obscured_aperture_otf(1.0, eta), 0.0);
  }
}

TEST(SensorOtf, FftRoundTripsAndMatchesTheDft) {
  constexpr int n = 16;
  std::vector<double> re(n), im(n), re0(n), im0(n);
  for (int i = 0; i < n; ++i) re0[i] = re[i] = std::sin(0.7 * i) + 0.1 * i, im0[i] = im[i] = std::cos(1.3 * i);
  fft_radix2(re.data(), im.data(), n, false);
  for (int k = 0; k < n; ++k) {
    std::complex<double> sum = 0;
    for (int i = 0; i < n; ++i)
      sum += std::complex<double>(re0[i], im0[i]) * std::polar(1.0, -2 * std::numbers::pi * k * i / n);
    EXPECT_NEAR(re[k], sum.real(), 1e-9);
    EXPECT_NEAR(im[k], sum.imag(), 1e-9);
  }
  fft_radix2(re.data(), im.data(), n, true);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(re[i], re0[i], 1e-12);
}

SensorParams blurry_camera() {
  SensorParams p;
  p.optics.f_number = 8.0;
  p.optics.obscuration = 0.3;
  p.optics.defocus_px = 1.5;
  p.optics.jitter_rms_px = 0.7;
  p.optics.smear_px = 2.0;
  return p;
}

// The blur conserves energy: on a periodic grid (powers of two, no margin) the sum of each plane
// is kept to rounding, while its peak drops; apply_optics on a plane dark at its edges keeps the
// sum up to the PSF's far diffraction tail (light scattered past the border, less the mirrored
// surroundings' light scattered in).
TEST(SensorBlur, ConservesEnergy) {
  constexpr int w = 128, h = 64;
  std::vector<std::vector<float>> planes(3, std::vector<float>(w * h, 0.0f));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double r2 = (x - 60.3) * (x - 60.3) + (y - 30.8) * (y - 30.8);
      planes[0][y * w + x] = static_cast<float>(std::exp(-r2 / 8.0));
      planes[1][y * w + x] = (x == 50 && y == 40) ? 1000.0f : 0.0f;  // a point
      planes[2][y * w + x] = (std::abs(x - 60) < 3 && std::abs(y - 30) < 2) ? 3.0f : 0.0f;
    }
  const auto sum_and_peak = [](const std::vector<float>& p) {
    double s = 0;
    float m = 0;
    for (float v : p) s += v, m = std::max(m, v);
    return std::pair{s, m};
  };
  const std::vector<SensorChannel> channels{monochromatic_channel("a", 550, 80), monochromatic_channel("b", 850, 80),
                                            monochromatic_channel("c", 450, 80)};
  const SensorParams p = blurry_camera();
  std::vector<PlaneOtf> otfs;
  for (const SensorChannel& c : channels) otfs.push_back(channel_plane_otf(p, c, 3.0));
  std::vector<std::vector<float>> periodic = planes, padded = planes;
  filter_planes(periodic, w, h, otfs, 0);
  apply_optics(padded, w, h, channels, p, 3.0);
  for (size_t c = 0; c < planes.size(); ++c) {
    const auto [s0, m0] = sum_and_peak(planes[c]);
    const auto [s1, m1] = sum_and_peak(periodic[c]);
    const auto [s2, m2] = sum_and_peak(padded[c]);
    EXPECT_NEAR(s1 / s0, 1.0, 1e-6) << "plane " << c;
    EXPECT_LT(m1, 0.5 * m0) << "plane " << c << " was not blurred";
    EXPECT_NEAR(s2 / s0, 1.0, 0.02) << "plane " << c;
  }
}

TEST(SensorSampling, DetectorsAverageTheirAreaForAnyRatio) {
  constexpr int w = 50, h = 31;
  std::vector<float> img(w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img[y * w + x] = static_cast<float>(2.0 * x + 0.25 * y + ((x * 7 + y * 3) % 5));
  for (double ratio : {1.0, 2.0, 2.7, 4.0}) {
    const DetectorGrid g = make_detector_grid(w, h, ratio);
    EXPECT_EQ(g.width, static_cast<int>(w / ratio));
    const std::vector<float> d = integrate_detectors(img, w, h, g);
    // The mean of the piecewise-constant image over each detector's square, by the midpoint rule
    // (its own error: a jump of up to 6 over 1/100 of a pixel).
    constexpr int s = 270;
    for (int j = 0; j < g.height; ++j)
      for (int i = 0; i < g.width; ++i) {
        double sum = 0;
        for (int b = 0; b < s; ++b)
          for (int a = 0; a < s; ++a) {
            const int x = static_cast<int>(g.x0 + (i + (a + 0.5) / s) * ratio);
            const int y = static_cast<int>(g.y0 + (j + (b + 0.5) / s) * ratio);
            sum += img[y * w + x];
          }
        EXPECT_NEAR(d[j * g.width + i], sum / (s * s), 0.02) << ratio << " " << i << " " << j;
      }
  }
  EXPECT_THROW(make_detector_grid(10, 10, 11.0), Error);
}

// A half-plane edge through (cx, cy) at `angle` from the y axis, exactly area-sampled (32² points
// per pixel): dark 0.2, bright 1.0.
std::vector<float> slanted_edge(int w, int h, double angle) {
  const double nx = std::cos(angle), ny = -std::sin(angle), cx = w / 2.0, cy = h / 2.0;
  std::vector<float> img(static_cast<size_t>(w) * h);
  constexpr int s = 32;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int bright = 0;
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) bright += ((x + (i + 0.5) / s - cx) * nx + (y + (j + 0.5) / s - cy) * ny) > 0;
      img[static_cast<size_t>(y) * w + x] = static_cast<float>(0.2 + 0.8 * bright / (s * s));
    }
  return img;
}

// ISO 12233-style (tests/support/slanted_edge.h), against the known edge through the centre.
double slanted_edge_mtf(const std::vector<float>& d, const DetectorGrid& g, double cx_render, double cy_render,
                        double angle, double f) {
  const double nx = std::cos(angle), ny = -std::sin(angle);
  std::vector<test::EdgeSample> samples;
  for (int j = 6; j < g.height - 6; ++j)
    for (int i = 0; i < g.width; ++i) {
      const double px = g.x0 + (i + 0.5) * g.ratio, py = g.y0 + (j + 0.5) * g.ratio;
      const double dist = ((px - cx_render) * nx + (py - cy_render) * ny) / g.ratio;  // pitches
      samples.push_back({dist, d[static_cast<size_t>(j) * g.width + i]});
    }
  int empty = 0;
  const double mtf = test::edge_mtf(samples, f, &empty);
  EXPECT_EQ(empty, 0) << "empty bins: the edge is not slanted enough";
  return mtf;
}

TEST(SensorSlantedEdge, RecoversTheImplementedMtfAtNyquist) {
  constexpr int w = 320, h = 320;
  const double angle = 5.0 * std::numbers::pi / 180.0;
  const std::vector<float> edge = slanted_edge(w, h, angle);
  struct Case {
    double f_number, obscuration, defocus_px, jitter_px, ratio;
  };
  for (const Case& c : {Case{2.8, 0.0, 0.0, 0.0, 4.0}, Case{4.0, 0.35, 0.3, 0.2, 4.0}, Case{1.4, 0.0, 0.0, 0.3, 5.0}}) {
    SensorParams p;
    p.optics.f_number = c.f_number;
    p.optics.obscuration = c.obscuration;
    p.optics.defocus_px = c.defocus_px;
    p.optics.jitter_rms_px = c.jitter_px;
    const SensorChannel green = monochromatic_channel("G", 550.0, 80.0);
    std::vector<std::vector<float>> planes{edge};
    apply_optics(planes, w, h, {green}, p, c.ratio);
    const DetectorGrid g = make_detector_grid(w, h, c.ratio);
    const std::vector<float> d = integrate_detectors(planes[0], w, h, g);
    for (double f : {0.25, 0.5}) {
      const double measured = slanted_edge_mtf(d, g, w / 2.0, h / 2.0, angle, f);
      const double implemented =
          system_otf(p.optics, p.sampling.pitch_um, green, f * std::cos(angle), -f * std::sin(angle));
      EXPECT_NEAR(measured / implemented, 1.0, 0.05)
          << "f/" << c.f_number << " obscuration " << c.obscuration << " at " << f << " cycles/pitch: measured "
          << measured << ", implemented " << implemented;
    }
  }
}

}  // namespace
}  // namespace sylva
