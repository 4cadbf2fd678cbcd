#pragma once
// The detector grid over a render (docs/sensors.md, "Sampling"): detectors of `ratio` render pixels
// on a side (any real ratio >= 1), as many as fit, centred; each detector's value is the mean of
// the render over its square, render pixels weighted by the area they share with it.

#include <vector>

namespace sylva {

struct DetectorGrid {
  int width = 0, height = 0;  // detectors
  double ratio = 1.0;         // render pixels per detector pitch
  double x0 = 0.0, y0 = 0.0;  // render-pixel position of detector (0, 0)'s top-left corner
};

// Throws sylva::Error when not one detector fits (`ratio` larger than the render).
DetectorGrid make_detector_grid(int render_width, int render_height, double ratio);

// The mean of `plane` (render_width × render_height, row-major) over each detector of `grid`.
std::vector<float> integrate_detectors(const std::vector<float>& plane, int render_width, int render_height,
                                       const DetectorGrid& grid);

}  // namespace sylva
