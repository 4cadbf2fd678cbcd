#pragma once
// Terrain: a regular grid of heights over the world's x–y plane (a height field), meshed as two
// triangles per cell, and the height of exactly that mesh at any (x, y), for placing trees, grass
// and targets on it. Weber & Penn §6 place their trees over elevation maps of 1–2 m per sample.
// Plain data and pure functions: no I/O (rasters are read by scenes/), no Embree.

#include "geometry/mesh.h"

#include <cstdint>
#include <vector>

namespace sylva {

// Heights at the nodes of a regular grid, in world order: node (i, j) lies at
// (min_m.x + i·spacing_m.x, min_m.y + j·spacing_m.y), row j = 0 the SOUTH edge (a raster's bottom
// row). `heights[j·width + i]` in metres. At least 2 × 2 nodes.
struct HeightField {
  int width = 0, height = 0;
  Vec2 min_m{0.0f};
  Vec2 spacing_m{1.0f};
  std::vector<float> heights;

  float at(int i, int j) const { return heights[static_cast<size_t>(j) * static_cast<size_t>(width) + i]; }
  Vec2 max_m() const { return min_m + spacing_m * Vec2(static_cast<float>(width - 1), static_cast<float>(height - 1)); }
};

// The mesh of a height field: one vertex per node (shared by every cell around it, so the surface
// is watertight: no cracks), two triangles per cell split along the diagonal from node (i, j) to
// (i+1, j+1), counter-clockwise seen from above, smooth shading normals from central differences.
TriangleMesh make_terrain_mesh(const HeightField& field);

// The height of make_terrain_mesh's surface at (x, y): linear over the triangle containing the
// point, so exact to the rendered surface (up to float rounding). Outside the grid the point is
// clamped to its edge.
float terrain_height(const HeightField& field, Vec2 xy);
// The lowest point of the surface over the disc of `radius_m` about `centre` (a trunk's footprint),
// exactly: per triangle, the minimum over its corners in the disc, its edges' crossings with the
// rim and the rim point against its gradient.
float terrain_min_height(const HeightField& field, Vec2 centre, float radius_m);

// Resamples a raster of heights (row 0 the NORTH edge, as images are stored; `values[y·width + x]`
// in metres at pixel centres) onto a grid of every `step`-th sample spanning the same pixel centres:
// ceil((width − 1) / step) + 1 nodes across, evenly spaced, heights bilinear between pixel centres
// (step 1 keeps every pixel). `min_m` is the world (x, y) of the south-west pixel's centre,
// `pixel_m` the pixel size.
HeightField resample_height_raster(const std::vector<float>& values, int width, int height, Vec2 min_m, float pixel_m,
                                   int step);

// A procedural terrain: hash-based value noise summed over octaves (fBm), or ridged noise
// (1 − |noise| per octave, sharp crests), Musgrave's terrain models (Ebert et al., *Texturing and
// Modeling*, ch. 16).
struct ProceduralTerrainParams {
  Vec2 size_m{200.0f, 200.0f};  // extent, centred on `centre_m`
  Vec2 centre_m{0.0f};
  float resolution_m = 1.0f;      // node spacing (at most; the grid fits the size exactly)
  float relief_m = 8.0f;          // peak-to-trough height range (the heights span [0, relief])
  float feature_size_m = 120.0f;  // wavelength of the first octave
  int octaves = 5;
  float gain = 0.5f;  // amplitude ratio between octaves (lacunarity 2)
  bool ridged = false;
  uint64_t seed = 1;
};
HeightField make_procedural_terrain(const ProceduralTerrainParams& params);

// Smooth 2-D value noise in [−1, 1] on an integer lattice hashed from `seed` (quintic fade).
float value_noise(uint64_t seed, Vec2 p);

}  // namespace sylva
