#pragma once
// The sensor stage of the render call (docs/sensors.md): a scene's [sensor] applied to the finished
// image — the render's EXR keeps the pre-sensor radiance — and written beside it as OUT.sensor.exr
// (digital numbers and the noise-free optical radiance on the detector grid, the calibration and
// seeds in the header), OUT.sensor.json (the same record) and, with a preview, OUT.sensor.png.

#include "pipeline/scene_request.h"
#include "sensor/sensor.h"

#include <filesystem>

namespace sylva {

struct SensorOutputPaths {
  std::filesystem::path exr, json, png;
};
// OUT.exr → OUT.sensor.exr, OUT.sensor.json and (when `png` is not empty) OUT.sensor.png.
SensorOutputPaths sensor_output_paths(const std::filesystem::path& exr, const std::filesystem::path& png);

// Before any work: a [sensor] needs radiance (not reflectance factors) and outputs that are not
// inputs of the scene. No-op without [sensor].
void check_sensor_stage(const RenderJob& job, const std::filesystem::path& exr, const std::filesystem::path& png);

// The camera's render pixel angle at the image centre and its distance to the target.
SensorGeometry sensor_geometry(const SceneFile& file, const RenderSettings& settings);
// The render's band channels as the sensor sees them.
std::vector<SensorChannel> sensor_channels(const RenderSettings& settings);
// The temporal noise seed: [sensor] noise_seed, else a hash of the render's seed.
uint64_t sensor_noise_seed(const SensorParams& params, const RenderSettings& settings);

// Applies the scene's [sensor] to `image` (the render's annotated image) and, when `exr` is not
// empty, writes its outputs. Returns the sensed image (its image empty without [sensor]).
SensedImage run_sensor_stage(const SceneFile& file, const RenderSettings& settings, const Image& image,
                             const std::filesystem::path& exr, const std::filesystem::path& png);

// The PNG of a sensed image: its digital numbers over the ADC's full scale, sRGB-encoded (the
// visible channels, else the first as grey).
void write_sensor_preview(const std::filesystem::path& png, const Image& sensed, const SensorParams& params);

}  // namespace sylva
