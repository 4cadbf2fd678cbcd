#pragma once
// The rasters of forest scenes (docs/scene_format.md, [terrain] and [vegetation]): an elevation
// raster becomes a HeightField, a 16-bit feature map a FeatureMap registered over the terrain.
// Errors are sylva::Error("file: what is wrong") naming the raster.

#include "geometry/placement.h"
#include "geometry/terrain.h"

#include <filesystem>
#include <optional>

namespace sylva {

struct ElevationRaster {
  float metres_per_pixel = 1.0f;
  float vertical_scale = 1.0f;  // metres per stored unit (16-bit integers or floats)
  float height_offset_m = 0.0f;
  std::optional<Vec2> origin_m;  // world (x, y) of the raster's south-west corner; none: centred
  int step = 1;
};

// The terrain of an elevation raster (16-bit unsigned integer or 16/32-bit float, one channel);
// heights at pixel centres, `extent_min/max` receive the raster's full extent (pixel edges), which
// a feature map covers.
HeightField read_elevation_raster(const std::filesystem::path& file, const ElevationRaster& options, Vec2* extent_min,
                                  Vec2* extent_max);

// A 16-bit unsigned one-channel feature map covering [extent_min, extent_max]. Its aspect ratio must
// match the extent's within 1 % (same extent, any resolution).
FeatureMap read_feature_map(const std::filesystem::path& file, Vec2 extent_min, Vec2 extent_max);

}  // namespace sylva
