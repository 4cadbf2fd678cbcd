#pragma once
// The sensor model as a stage after the render (docs/sensors.md): the pre-sensor radiance of each
// channel is filtered by the camera's optics at that channel's wavelengths, integrated over each
// detector of a coarser grid, and turned into digital numbers with the detector's noise; the
// render itself is not changed. On core only: the pipeline hands it the image, the channels'
// responses and the camera's pixel angle; Python hands it arrays.

#include "core/image.h"
#include "sensor/blur.h"
#include "sensor/detector.h"
#include "sensor/otf.h"
#include "sensor/resample.h"
#include "sensor/sensor_params.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sylva {

// Where the render's pixels point.
struct SensorGeometry {
  double render_pixel_rad = 0;  // angle of one render pixel at the image centre (0: unknown)
  double distance_m = 0;        // camera to its target, for the ground sample distance (0: unknown)
};

struct SensedImage {
  // On the detector grid: every channel's digital numbers (UInt) under its own name, and
  // `optical.<C>`, the noise-free radiance reaching each detector (after the optics and the
  // integration); header: the render's attributes and sylva:sensor:* (sensor_attributes).
  Image image;
  DetectorGrid grid;
  std::vector<ChannelCalibration> calibration;  // per channel, in order
  double integration_time_s = 0;
  uint64_t noise_seed = 0;
  double ifov_rad = 0;         // one detector's angle (0 when the geometry is unknown)
  double gsd_m = 0;            // ifov × distance (0 when unknown)
  double focal_length_mm = 0;  // pitch / ifov (0 when unknown)
  double seconds = 0;          // the stage's wall time
};

// Applies the sensor to `channels` of `radiance` (each must be a channel of it; radiance units).
// Throws sylva::Error for a detector grid that does not fit or a render coarser than the detectors.
SensedImage apply_sensor(const Image& radiance, const std::vector<SensorChannel>& channels, const SensorParams& params,
                         const SensorGeometry& geometry, uint64_t noise_seed);

// The stages alone, for tests: the optics' filter on the render grid (in place, `ratio` render
// pixels per pitch) and the whole optical path to the detector grid.
void apply_optics(std::vector<std::vector<float>>& planes, int width, int height,
                  const std::vector<SensorChannel>& channels, const SensorParams& params, double ratio);

// The filter apply_optics gives `channel` on a render grid of `ratio` render pixels per pitch
// (optics_otf, in cycles per render pixel).
PlaneOtf channel_plane_otf(const SensorParams& params, const SensorChannel& channel, double ratio);

// What a sensed image records (header and sidecar): the parameters, the seeds, the geometry and
// each channel's calibration, as key/value text.
std::vector<std::pair<std::string, std::string>> sensor_attributes(const SensedImage& sensed,
                                                                   const SensorParams& params);
// The same as a JSON document (the sensor sidecar).
std::string sensor_json(const SensedImage& sensed, const SensorParams& params);

}  // namespace sylva
