#include "pipeline/sensor_stage.h"

#include "core/error.h"
#include "core/hash.h"
#include "core/output_paths.h"

#include <cmath>
#include <type_traits>
#include <variant>

namespace sylva {

namespace {

std::filesystem::path with_suffix(const std::filesystem::path& p, const char* suffix) {
  std::filesystem::path out = p;
  out.replace_filename(p.stem().string() + suffix);
  return out;
}

}  // namespace

SensorOutputPaths sensor_output_paths(const std::filesystem::path& exr, const std::filesystem::path& png) {
  SensorOutputPaths paths;
  if (exr.empty()) return paths;
  paths.exr = with_suffix(exr, ".sensor.exr");
  paths.json = with_suffix(exr, ".sensor.json");
  if (!png.empty()) paths.png = with_suffix(png, ".sensor.png");
  return paths;
}

void check_sensor_stage(const RenderJob& job, const std::filesystem::path& exr, const std::filesystem::path& png) {
  if (!job.file.sensor) return;
  if (job.settings.quantity != Quantity::radiance)
    throw Error("[sensor] needs radiance: render with --quantity radiance (the sensor counts photons)");
  const SensorOutputPaths paths = sensor_output_paths(exr, png);
  check_outputs({{"-o", exr}, {"sensor EXR", paths.exr}, {"sensor sidecar", paths.json}, {"sensor PNG", paths.png}},
                job.file.inputs);
}

SensorGeometry sensor_geometry(const SceneFile& file, const RenderSettings& settings) {
  const CameraDesc& camera = file.scene.camera;
  SensorGeometry g;
  g.distance_m = glm::length(camera.target - camera.position);
  std::visit(
      [&](const auto& projection) {
        using P = std::decay_t<decltype(projection)>;
        if constexpr (std::is_same_v<P, PerspectiveProjection>) {
          const double half = projection.vfov_deg * 0.5 * 3.14159265358979323846 / 180.0;
          g.render_pixel_rad = 2.0 * std::tan(half) / settings.height;
        } else if constexpr (std::is_same_v<P, OrthographicProjection>) {
          // A parallel view: the pixel's size at the target's distance.
          const double pixel_m = projection.width_m / settings.width;
          g.render_pixel_rad = g.distance_m > 0 ? pixel_m / g.distance_m : 0.0;
        }
      },
      camera.projection);
  return g;
}

std::vector<SensorChannel> sensor_channels(const RenderSettings& settings) {
  std::vector<SensorChannel> channels;
  for (const Band& band : settings.bands)
    for (size_t c = 0; c < band.channels.size(); ++c)
      channels.push_back(describe_channel(band.channels[c], band.name, band.weights[c]));
  return channels;
}

uint64_t sensor_noise_seed(const SensorParams& params, const RenderSettings& settings) {
  return params.noise_seed ? *params.noise_seed : hash_ids(settings.seed, 0x5e4507ull);
}

SensedImage run_sensor_stage(const SceneFile& file, const RenderSettings& settings, const Image& image,
                             const std::filesystem::path& exr, const std::filesystem::path& png) {
  if (!file.sensor) return {};
  const SensorParams& params = *file.sensor;
  SensedImage sensed = apply_sensor(image, sensor_channels(settings), params, sensor_geometry(file, settings),
                                    sensor_noise_seed(params, settings));
  if (!exr.empty()) {
    const SensorOutputPaths paths = sensor_output_paths(exr, png);
    write_exr(paths.exr, sensed.image);
    write_text_file(paths.json, sensor_json(sensed, params));
    if (!paths.png.empty()) write_sensor_preview(paths.png, sensed.image, params);
  }
  return sensed;
}

void write_sensor_preview(const std::filesystem::path& png, const Image& sensed, const SensorParams& params) {
  PreviewOptions preview;
  if (sensed.find_channel("R") < 0) preview.channels = {sensed.channels[0], sensed.channels[0], sensed.channels[0]};
  preview.view = "Standard";
  preview.exposure_ev = -static_cast<float>(std::log2(std::ldexp(1.0, params.detector.adc_bits) - 1.0));
  write_png_preview(png, sensed, preview);
}

}  // namespace sylva
