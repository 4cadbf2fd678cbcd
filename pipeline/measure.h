#pragma once
// The plot sensor's call (docs/radiometry.md, "Plot sensor"): a scene with a [plot] in, its BRF
// (or mean radiance) per view direction and its flux budget out, each as a CSV written atomically
// with a header that names the scene, its hash, bands, seed and sample counts. `sylva measure`
// parses its options and calls it. Never denoised: its figures are unbiased estimates with their
// standard errors.

#include "pipeline/render_call.h"
#include "render/sensors/plot_sensor.h"

#include <filesystem>
#include <optional>

namespace sylva {

struct MeasureCallOptions {
  RenderRequest request;       // the scene and its overrides (quantity: reflectance unless asked)
  std::filesystem::path brf;   // the BRF table (empty: not measured)
  std::filesystem::path flux;  // the flux budget (empty: not measured)
  int samples = 0;             // rays per view direction (0: [plot] samples)
  int flux_samples = 0;        // light paths of the flux budget (0: [plot] flux_samples)
};

struct MeasureResult {
  std::optional<BrfTable> brf;
  std::optional<FluxTable> flux;
  double brf_seconds = 0, flux_seconds = 0;
};

// Throws ParseError / sylva::Error before any work for a scene without [plot], a BRF without view
// directions, or an output that would replace an input.
MeasureResult measure_scene(const MeasureCallOptions& options, RenderObserver& observer);

}  // namespace sylva
