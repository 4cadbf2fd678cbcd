#include "scenes/forest_rasters.h"

#include "core/error.h"
#include "core/image.h"

#include <fmt/core.h>

#include <cmath>

namespace sylva {

HeightField read_elevation_raster(const std::filesystem::path& file, const ElevationRaster& options, Vec2* extent_min,
                                  Vec2* extent_max) {
  const Raster r = read_raster(file);
  if (r.type != RasterType::UInt16 && r.type != RasterType::Half && r.type != RasterType::Float)
    throw Error(fmt::format("{}: an elevation raster needs 16-bit unsigned integer or float samples, not {}",
                            file.string(), raster_type_name(r.type)));
  if (r.width < 2 || r.height < 2)
    throw Error(fmt::format("{}: an elevation raster needs at least 2 x 2 pixels, not {} x {}", file.string(), r.width,
                            r.height));
  std::vector<float> heights(r.values.size());
  for (size_t i = 0; i < heights.size(); ++i) {
    if (!std::isfinite(r.values[i]))
      throw Error(fmt::format("{}: pixel ({}, {}) is not a finite height", file.string(),
                              i % static_cast<size_t>(r.width), i / static_cast<size_t>(r.width)));
    heights[i] = r.values[i] * options.vertical_scale + options.height_offset_m;
  }
  const float px = options.metres_per_pixel;
  const Vec2 size(px * static_cast<float>(r.width), px * static_cast<float>(r.height));
  const Vec2 lo = options.origin_m ? *options.origin_m : -0.5f * size;
  *extent_min = lo;
  *extent_max = lo + size;
  return resample_height_raster(heights, r.width, r.height, lo + Vec2(0.5f * px), px, options.step);
}

FeatureMap read_feature_map(const std::filesystem::path& file, Vec2 extent_min, Vec2 extent_max) {
  const Raster r = read_raster(file);
  if (r.type != RasterType::UInt16)
    throw Error(fmt::format("{}: a feature map needs 16-bit unsigned integer samples, not {}", file.string(),
                            raster_type_name(r.type)));
  const Vec2 size = extent_max - extent_min;
  const double map_aspect = static_cast<double>(r.width) / r.height;
  const double terrain_aspect = static_cast<double>(size.x) / size.y;
  if (std::abs(map_aspect / terrain_aspect - 1.0) > 0.01)
    throw Error(
        fmt::format("{}: the feature map is {} x {} pixels but the terrain is {:g} x {:g} m; a feature map "
                    "covers the terrain's extent, so their aspect ratios must match",
                    file.string(), r.width, r.height, size.x, size.y));
  FeatureMap map;
  map.width = r.width;
  map.height = r.height;
  map.min_m = extent_min;
  map.max_m = extent_max;
  map.bits.reserve(r.values.size());
  for (const float v : r.values) map.bits.push_back(static_cast<uint16_t>(v));
  return map;
}

}  // namespace sylva
