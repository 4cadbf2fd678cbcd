#include "sensor/resample.h"

#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace sylva {

namespace {

// The render pixels detector column (or row) i covers and the share of each: [start, start + n).
struct Footprint {
  int start = 0;
  std::vector<double> weight;  // overlap length / ratio
};

std::vector<Footprint> footprints(int count, double origin, double ratio) {
  std::vector<Footprint> out(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double a = origin + i * ratio, b = a + ratio;
    Footprint& f = out[static_cast<size_t>(i)];
    f.start = static_cast<int>(std::floor(a));
    for (int p = f.start; p < b; ++p) {
      const double overlap = std::min<double>(b, p + 1) - std::max<double>(a, p);
      f.weight.push_back(std::max(0.0, overlap) / ratio);
    }
  }
  return out;
}

}  // namespace

DetectorGrid make_detector_grid(int render_width, int render_height, double ratio) {
  DetectorGrid g;
  g.ratio = ratio;
  g.width = static_cast<int>(std::floor(render_width / ratio + 1e-9));
  g.height = static_cast<int>(std::floor(render_height / ratio + 1e-9));
  if (g.width < 1 || g.height < 1)
    throw Error(fmt::format("the sensor's detectors ({:.3g} render pixels each) do not fit the {}x{} render", ratio,
                            render_width, render_height));
  g.x0 = (render_width - g.width * ratio) / 2;
  g.y0 = (render_height - g.height * ratio) / 2;
  return g;
}

std::vector<float> integrate_detectors(const std::vector<float>& plane, int render_width, int render_height,
                                       const DetectorGrid& grid) {
  const std::vector<Footprint> fx = footprints(grid.width, grid.x0, grid.ratio);
  const std::vector<Footprint> fy = footprints(grid.height, grid.y0, grid.ratio);
  std::vector<float> out(static_cast<size_t>(grid.width) * grid.height);
  for (int j = 0; j < grid.height; ++j) {
    const Footprint& ry = fy[static_cast<size_t>(j)];
    for (int i = 0; i < grid.width; ++i) {
      const Footprint& rx = fx[static_cast<size_t>(i)];
      double sum = 0;
      for (size_t b = 0; b < ry.weight.size(); ++b) {
        const int y = std::min(ry.start + static_cast<int>(b), render_height - 1);
        const float* row = &plane[static_cast<size_t>(y) * render_width];
        for (size_t a = 0; a < rx.weight.size(); ++a)
          sum += ry.weight[b] * rx.weight[a] * row[std::min(rx.start + static_cast<int>(a), render_width - 1)];
      }
      out[static_cast<size_t>(j) * grid.width + i] = static_cast<float>(sum);
    }
  }
  return out;
}

}  // namespace sylva
