// The detector of the sensor model: the photon-transfer curve recovers the gain and the read
// noise; a uniform blackbody plate gives the set NETD; the fixed patterns stay over frames; the
// whole stage is deterministic; the camera equation and the calibration agree.
#include "core/hash.h"
#include "sensor/detector.h"
#include "sensor/presets.h"
#include "sensor/sensor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace sylva {
namespace {

struct Moments {
  double mean = 0, var = 0;
};

// Mean of (a + b) / 2 and the temporal variance var(a - b) / 2 (fixed patterns cancel).
Moments frame_pair_moments(const std::vector<float>& a, const std::vector<float>& b) {
  const double n = static_cast<double>(a.size());
  double sum = 0, dsum = 0, dsum2 = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sum += (a[i] + b[i]) / 2.0;
    const double d = static_cast<double>(a[i]) - b[i];
    dsum += d;
    dsum2 += d * d;
  }
  return {sum / n, (dsum2 / n - (dsum / n) * (dsum / n)) / 2.0 * n / (n - 1)};
}

SensorParams ptc_camera() {
  SensorParams p;
  DetectorParams& d = p.detector;
  d.gain_e_per_dn = 2.0;
  d.read_noise_e = 5.0;
  d.full_well_e = 12000.0;
  d.adc_bits = 14;
  d.offset_dn = 64.0;
  d.dark_current_e_per_s = 0.0;
  d.prnu = 0.01;
  d.dsnu_e = 2.0;
  return p;
}

// Variance against mean on uniform plates, fitted by weighted least squares (weights 1/var², the
// variance of a variance estimate being 2 var² / n): slope 1/gain, intercept (σ_read/gain)² + 1/12.
TEST(SensorDetector, PhotonTransferCurveRecoversGainAndReadNoise) {
  const SensorParams p = ptc_camera();
  const SensorChannel c = monochromatic_channel("G", 550.0, 80.0);
  const double t = 1e-3;
  const ChannelCalibration cal = calibrate_channel(p, c, t);
  constexpr int w = 128, h = 128;
  double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (double electrons : {0.0, 10.0, 40.0, 150.0, 500.0, 1500.0, 4000.0, 9000.0}) {
    const std::vector<float> plate(w * h, static_cast<float>(electrons / cal.electrons_per_radiance));
    const std::vector<float> a = detect_channel(plate, w, h, 0, p, cal, c, t, 11);
    const std::vector<float> b = detect_channel(plate, w, h, 0, p, cal, c, t, 12);
    const Moments m = frame_pair_moments(a, b);
    const double x = m.mean - cal.dn_offset, weight = 1.0 / (m.var * m.var);
    sw += weight, sx += weight * x, sy += weight * m.var, sxx += weight * x * x, sxy += weight * x * m.var;
  }
  const double slope = (sw * sxy - sx * sy) / (sw * sxx - sx * sx), intercept = (sy - slope * sx) / sw;
  const double gain = 1.0 / slope, read_noise = gain * std::sqrt(intercept - 1.0 / 12.0);
  EXPECT_NEAR(gain / 2.0, 1.0, 0.03) << "gain " << gain << " e-/DN";
  EXPECT_NEAR(read_noise / 5.0, 1.0, 0.05) << "read noise " << read_noise << " e-";
}

TEST(SensorDetector, PoissonCountsHaveTheirMeanAsVariance) {
  for (double mean : {0.7, 6.0, 29.0, 31.0, 300.0}) {
    double s = 0, s2 = 0;
    constexpr int n = 40000;
    for (int i = 0; i < n; ++i) {
      const double k = hashed_poisson(hash_ids(5, static_cast<uint64_t>(i)), mean);
      s += k, s2 += k * k;
    }
    const double m = s / n, v = s2 / n - m * m;
    // 5 standard errors of the mean and of the variance (≈ sqrt(2/n) relative, plus the kurtosis).
    EXPECT_NEAR(m, mean, 5 * std::sqrt(mean / n)) << mean;
    EXPECT_NEAR(v / mean, 1.0, 5 * std::sqrt(2.0 / n + 1.0 / (mean * n))) << mean;
  }
}

// The thermal path: a uniform 300 K blackbody plate at 10 µm through the whole stage (optics,
// detectors, NETD, fixed patterns, 14-bit ADC); the temporal noise of the calibrated radiance over
// dL/dT is the NETD. Sylva has no thermal bands yet, so the plate is an array in radiance units.
TEST(SensorDetector, UniformBlackbodyPlateGivesTheSetNetd) {
  SensorParams p = find_sensor_preset("lwir_640_50mk")->params;
  const SensorChannel lwir = monochromatic_channel("lwir.Y", 10000.0, 4000.0);
  const double l300 = planck_radiance(10000.0, 300.0);
  Image plate = make_image(256, 256, {"lwir.Y"});
  for (float& v : plate.pixels) v = static_cast<float>(l300);
  SensorGeometry geometry;
  geometry.render_pixel_rad = 1e-3;
  for (double netd_mk : {50.0, 120.0}) {
    p.detector.netd_mk = netd_mk;
    const SensedImage a = apply_sensor(plate, {lwir}, p, geometry, 1);
    const SensedImage b = apply_sensor(plate, {lwir}, p, geometry, 2);
    std::vector<float> da, db;
    for (int y = 0; y < a.grid.height; ++y)
      for (int x = 0; x < a.grid.width; ++x) da.push_back(a.image.at(x, y, 0)), db.push_back(b.image.at(x, y, 0));
    const Moments m = frame_pair_moments(da, db);
    const double sigma_l = std::sqrt(m.var) * a.calibration[0].radiance_per_dn;
    const double measured_mk = sigma_l / planck_radiance_dt(10000.0, 300.0) * 1e3;
    EXPECT_NEAR(measured_mk / netd_mk, 1.0, 0.03) << "measured NETD " << measured_mk << " mK";
    // The calibration gives the plate's radiance back (fixed patterns average out).
    EXPECT_NEAR((m.mean - a.calibration[0].dn_offset) * a.calibration[0].radiance_per_dn / l300, 1.0, 1e-3);
  }
}

TEST(SensorDetector, CalibrationMapsDigitalNumbersBackToRadiance) {
  SensorParams p = ptc_camera();
  p.detector.read_noise_e = 0, p.detector.shot_noise = false, p.detector.prnu = 0, p.detector.dsnu_e = 0;
  p.detector.dark_current_e_per_s = 2000.0;
  const SensorChannel c = monochromatic_channel("G", 550.0, 80.0);
  const ChannelCalibration cal = calibrate_channel(p, c, 2e-3);
  for (double l : {0.001, 0.01, 0.03, 0.05}) {
    const std::vector<float> dn =
        detect_channel(std::vector<float>(4, static_cast<float>(l)), 2, 2, 0, p, cal, c, 2e-3, 1);
    if (l < cal.saturation_radiance) {
      EXPECT_NEAR(cal.radiance_per_dn * (dn[0] - cal.dn_offset) / l, 1.0, 0.01) << l;
    }
  }
  // Saturation: past the full well every detector reads the same clipped number.
  const std::vector<float> bright = detect_channel(
      std::vector<float>(4, static_cast<float>(cal.saturation_radiance * 3)), 2, 2, 0, p, cal, c, 2e-3, 1);
  EXPECT_NEAR(cal.radiance_per_dn * (bright[0] - cal.dn_offset) / cal.saturation_radiance, 1.0, 0.01);
  // The camera equation by hand: π τ / (1 + 4N²) · p² · Δλ · λ / (h c) · QE.
  const double n = p.optics.f_number, pitch = p.sampling.pitch_um * 1e-6;
  const double by_hand = std::numbers::pi * p.optics.transmittance / (1 + 4 * n * n) * pitch * pitch * 80.0 * 550e-9 /
                         (6.62607015e-34 * 299792458.0) * p.detector.qe;
  EXPECT_NEAR(electron_rate_per_radiance(p, c, p.detector.qe) / by_hand, 1.0, 1e-9);
}

Image test_scene(int w, int h) {
  Image img = make_image(w, h, {"R", "G", "B"});
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = 0.02f * (1 + c) * (1.0f + std::sin(0.2f * x) * std::cos(0.15f * y));
  return img;
}

std::vector<SensorChannel> rgb_channels() {
  return {monochromatic_channel("R", 610, 90), monochromatic_channel("G", 550, 90),
          monochromatic_channel("B", 460, 90)};
}

TEST(SensorDeterminism, SameSeedsSameNumbersAndFixedPatternsStayOverFrames) {
  const Image img = test_scene(96, 64);
  SensorParams p = find_sensor_preset("phone_8bit")->params;
  SensorGeometry geometry;
  geometry.render_pixel_rad = 2e-4;
  geometry.distance_m = 50;
  const SensedImage a = apply_sensor(img, rgb_channels(), p, geometry, 7);
  const SensedImage b = apply_sensor(img, rgb_channels(), p, geometry, 7);
  EXPECT_EQ(a.image.pixels, b.image.pixels);
  EXPECT_EQ(a.image.attributes, b.image.attributes);
  const SensedImage c = apply_sensor(img, rgb_channels(), p, geometry, 8);
  EXPECT_NE(a.image.pixels, c.image.pixels) << "another noise seed, the same noise";
  EXPECT_EQ(a.image.attribute("sylva:sensor:noise_seed"), "7");
  EXPECT_NEAR(a.gsd_m, 2 * 2e-4 * 50, 1e-12);
  // Without temporal noise the frames are equal (only the fixed patterns remain) and another
  // fixed-pattern seed changes them.
  p.detector.shot_noise = false, p.detector.read_noise_e = 0;
  const SensedImage f1 = apply_sensor(img, rgb_channels(), p, geometry, 1);
  const SensedImage f2 = apply_sensor(img, rgb_channels(), p, geometry, 2);
  EXPECT_EQ(f1.image.pixels, f2.image.pixels);
  p.seed = 99;
  const SensedImage f3 = apply_sensor(img, rgb_channels(), p, geometry, 1);
  EXPECT_NE(f1.image.pixels, f3.image.pixels);
}

TEST(SensorDeterminism, PresetsAreNamedWithSources) {
  ASSERT_GE(sensor_presets().size(), 3u);
  for (const SensorPreset& preset : sensor_presets()) {
    EXPECT_FALSE(preset.source.empty()) << preset.name;
    EXPECT_EQ(preset.params.preset, preset.name);
  }
  EXPECT_EQ(find_sensor_preset("no such camera"), nullptr);
}

}  // namespace
}  // namespace sylva
