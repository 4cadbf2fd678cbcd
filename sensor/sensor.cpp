#include "sensor/sensor.h"

#include "core/error.h"
#include "sensor/blur.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace sylva {

namespace {}  // namespace

// The channel's radial OTF (every factor but the smear) tabulated over |f| in cycles per render
// pixel, linear between entries, and the smear's sinc along x: the filter evaluates it at every
// frequency of a padded grid, so it reads a table instead of 16 wavelengths' diffraction.
PlaneOtf channel_plane_otf(const SensorParams& params, const SensorChannel& channel, double ratio) {
  OpticsParams radial = params.optics;
  radial.smear_px = 0;
  constexpr int kEntries = 4096;
  const double rho_max = std::sqrt(0.5) * 1.0001;  // cycles per render pixel at the grid's corner
  auto table = std::make_shared<std::vector<double>>(kEntries + 1);
  for (int i = 0; i <= kEntries; ++i)
    (*table)[static_cast<size_t>(i)] =
        optics_otf(radial, params.sampling.pitch_um, channel, rho_max * i / kEntries * ratio, 0.0);
  const double smear = params.optics.smear_px * ratio;  // render pixels
  return [table, rho_max, smear](double fx, double fy) {
    const double x = std::sqrt(fx * fx + fy * fy) / rho_max * kEntries;
    const int i = std::min(static_cast<int>(x), kEntries - 1);
    const double t = x - i;
    double h = (*table)[static_cast<size_t>(i)] * (1 - t) + (*table)[static_cast<size_t>(i) + 1] * t;
    if (smear > 0 && fx != 0) h *= std::sin(std::numbers::pi * smear * fx) / (std::numbers::pi * smear * fx);
    return h;
  };
}

namespace {

// The PSF's reach in render pixels, for the mirrored margin.
int optics_margin(const SensorParams& params, const std::vector<SensorChannel>& channels, double ratio) {
  double longest = 0;
  for (const SensorChannel& c : channels)
    for (double l : c.lambda_nm) longest = std::max(longest, l);
  const OpticsParams& o = params.optics;
  const double airy_px = longest * 1e-3 * o.f_number / params.sampling.pitch_um;
  const double reach = 2.0 + 4.0 * airy_px + 3.0 * o.defocus_px + 4.0 * o.jitter_rms_px + o.smear_px;
  return static_cast<int>(std::ceil(reach * ratio)) + 4;
}

std::vector<float> plane_of(const Image& image, const std::string& channel) {
  const int c = image.find_channel(channel);
  if (c < 0) throw Error(fmt::format("the sensor needs channel {}, which the image does not have", channel));
  std::vector<float> plane(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) plane[static_cast<size_t>(y) * image.width + x] = image.at(x, y, c);
  return plane;
}

// The integration time: the given one, or (auto exposure) the one that puts the 99th percentile of
// the brightest channel's photo-electrons at 70 % of the full well.
double integration_time(const SensorParams& params, const std::vector<SensorChannel>& channels,
                        const std::vector<std::vector<float>>& optical) {
  const DetectorParams& d = params.detector;
  const double given = d.integration_time_ms * 1e-3;
  if (!d.auto_exposure || d.thermal || optical.empty()) return given;
  std::vector<double> rate(optical.front().size(), 0.0);
  for (size_t c = 0; c < channels.size(); ++c) {
    const double k = electron_rate_per_radiance(params, channels[c], channel_qe(d, channels[c]));
    for (size_t i = 0; i < rate.size(); ++i) rate[i] = std::max(rate[i], k * std::max(0.0f, optical[c][i]));
  }
  const size_t at = std::min(rate.size() - 1, static_cast<size_t>(0.99 * static_cast<double>(rate.size())));
  std::nth_element(rate.begin(), rate.begin() + static_cast<std::ptrdiff_t>(at), rate.end());
  const double p99 = rate[at];
  return p99 > 0 ? 0.7 * d.full_well_e / p99 : given;
}

// The detector's angle and render pixels per detector.
void sampling_geometry(const SensorParams& params, const SensorGeometry& geometry, SensedImage& out) {
  const SamplingParams& s = params.sampling;
  if (s.focal_length_mm > 0) {
    if (geometry.render_pixel_rad <= 0)
      throw Error("[sensor] focal_length_mm needs a perspective or orthographic camera; give oversample instead");
    out.ifov_rad = s.pitch_um * 1e-6 / (s.focal_length_mm * 1e-3);
    out.grid.ratio = out.ifov_rad / geometry.render_pixel_rad;
    if (out.grid.ratio < 1.0)
      throw Error(fmt::format(
          "[sensor] a detector ({:.4g} urad) is smaller than a render pixel ({:.4g} urad): raise the render's "
          "resolution by {:.3g} or more, or narrow the camera",
          out.ifov_rad * 1e6, geometry.render_pixel_rad * 1e6, 1.0 / out.grid.ratio));
  } else {
    out.grid.ratio = s.oversample;
    out.ifov_rad = geometry.render_pixel_rad * s.oversample;
  }
  out.focal_length_mm = out.ifov_rad > 0 ? s.pitch_um * 1e-3 / out.ifov_rad : 0.0;
  out.gsd_m = out.ifov_rad * geometry.distance_m;
}

}  // namespace

void apply_optics(std::vector<std::vector<float>>& planes, int width, int height,
                  const std::vector<SensorChannel>& channels, const SensorParams& params, double ratio) {
  std::vector<PlaneOtf> otfs;
  for (const SensorChannel& c : channels) otfs.push_back(channel_plane_otf(params, c, ratio));
  filter_planes(planes, width, height, otfs, optics_margin(params, channels, ratio));
}

SensedImage apply_sensor(const Image& radiance, const std::vector<SensorChannel>& channels, const SensorParams& params,
                         const SensorGeometry& geometry, uint64_t noise_seed) {
  const auto t0 = std::chrono::steady_clock::now();
  SensedImage out;
  out.noise_seed = noise_seed;
  sampling_geometry(params, geometry, out);
  const int w = radiance.width, h = radiance.height;
  const double ratio = out.grid.ratio;
  out.grid = make_detector_grid(w, h, ratio);

  std::vector<std::vector<float>> planes;
  for (const SensorChannel& c : channels) planes.push_back(plane_of(radiance, c.name));
  apply_optics(planes, w, h, channels, params, ratio);
  std::vector<std::vector<float>> optical;
  for (const std::vector<float>& p : planes) optical.push_back(integrate_detectors(p, w, h, out.grid));
  out.integration_time_s = integration_time(params, channels, optical);

  std::vector<std::string> names;
  for (const SensorChannel& c : channels) names.push_back(c.name);
  for (const SensorChannel& c : channels) names.push_back("optical." + c.name);
  out.image = make_image(out.grid.width, out.grid.height, names);
  const int n = static_cast<int>(channels.size());
  for (int c = 0; c < n; ++c) {
    const SensorChannel& channel = channels[static_cast<size_t>(c)];
    out.calibration.push_back(calibrate_channel(params, channel, out.integration_time_s));
    const std::vector<float> dn =
        detect_channel(optical[static_cast<size_t>(c)], out.grid.width, out.grid.height, c, params,
                       out.calibration.back(), channel, out.integration_time_s, noise_seed);
    out.image.types[static_cast<size_t>(c)] = PixelType::UInt;
    for (int y = 0; y < out.grid.height; ++y)
      for (int x = 0; x < out.grid.width; ++x) {
        const size_t i = static_cast<size_t>(y) * out.grid.width + x;
        out.image.at(x, y, c) = dn[i];
        out.image.at(x, y, n + c) = optical[static_cast<size_t>(c)][i];
      }
  }
  out.image.attributes = radiance.attributes;
  for (auto& [key, value] : sensor_attributes(out, params)) out.image.set_attribute(key, value);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace sylva
