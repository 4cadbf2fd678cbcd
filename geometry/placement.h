#pragma once
// Vegetation placement over a terrain from a 16-bit feature map (Weber & Penn §6, plates 3–4):
// bits 0–13 each select one tree species (not mutually exclusive), bits 14–15 one of three grass
// types (0 = none). Trees of each species are spread by a deterministic point process over the
// cells where the species' bit is set, several variants (seeds) per species; grass is instanced as
// patches over the cells of each grass type. Pure functions of their inputs: no I/O, no Embree;
// every random decision is hashed from (seed, species, cell), so results never depend on threads.

#include "geometry/terrain.h"

#include <cstdint>
#include <vector>

namespace sylva {

inline constexpr int kFeatureTreeBits = 14;
inline constexpr int kFeatureGrassShift = 14;
inline constexpr int kFeatureGrassTypes = 3;

// A 16-bit raster registered over a rectangle of the world: pixel (0, 0) the north-west corner,
// rows running south (raster order), `bits[y·width + x]`.
struct FeatureMap {
  int width = 0, height = 0;
  Vec2 min_m{0.0f}, max_m{0.0f};  // world extent covered (south-west and north-east corners)
  std::vector<uint16_t> bits;

  // The pixel under (x, y); 0 outside the extent.
  uint16_t at(Vec2 xy) const;
};

// The grass type (1–3; 0 = none) a feature-map value selects.
inline int grass_type(uint16_t feature) { return feature >> kFeatureGrassShift; }

// One species' placement rule.
struct SpeciesPlacement {
  int bit = 0;                        // feature-map bit, 0–13
  double density_per_ha = 100.0;      // trees per hectare where the bit is set
  float min_spacing_m = 2.0f;         // no two trees of this species closer than this
  Vec2 scale_range{1.0f, 1.0f};       // uniform scale drawn from [min, max]
  std::vector<float> trunk_radius_m;  // one per variant (at scale 1): its footprint on the ground
};

// A placed tree: the base (trunk centre at the lowest terrain point under its footprint), heading
// about +Z, uniform scale, species index (into the SpeciesPlacement list) and variant.
struct PlacedTree {
  Vec3 base_m{0.0f};
  float heading_rad = 0.0f;
  float scale = 1.0f;
  uint16_t species = 0;
  uint16_t variant = 0;
};

// The point process: for each species, a jittered grid whose cells are 2·min_spacing wide (or
// smaller, down to the spacing implied by the density) with one candidate per cell, jittered inside
// the cell's central square of side (cell − min_spacing) so neighbours can never come closer than
// min_spacing, and kept with probability density·cell² (thinning: a Bernoulli process with the
// asked mean density) where the species' bit is set under it. Each cell's draws come from
// hash_ids(seed, species bit, cell x, cell y). Results are ordered by species, then cell row, then
// cell column, whatever the thread count. Throws sylva::Error if a density exceeds what its
// spacing allows (10⁴ / min_spacing² per ha).
std::vector<PlacedTree> place_trees(const FeatureMap& map, const HeightField& terrain,
                                    const std::vector<SpeciesPlacement>& species, uint64_t seed);

// A grass patch instance: centre on the terrain, heading, and the terrain's gradient there (the
// patch is sheared onto the local slope so every blade's base stays on the ground).
struct PlacedPatch {
  Vec3 centre_m{0.0f};
  float heading_rad = 0.0f;
  Vec2 slope{0.0f};    // dz/dx, dz/dy of the terrain across the patch
  int grass_type = 0;  // 1–3
};
// Patches of `patch_size_m[t − 1]` for each grass type t on a grid over the map's extent: a cell
// gets a patch of type t when the map's grass bits at its (jittered) centre say t; heading uniform,
// the centre jittered by up to a quarter cell, so the patches' repetition does not show.
std::vector<PlacedPatch> place_grass_patches(const FeatureMap& map, const HeightField& terrain,
                                             const std::vector<float>& patch_size_m, uint64_t seed);

// A procedural feature map for scenes without a raster: each pixel gets exactly one of `tree_bits`
// chosen by value noise of wavelength `patch_m` (so species form stands), trees on a fraction
// `tree_cover` of the area (clearings elsewhere), and a grass type 1..grass_types where
// another noise field exceeds 1 − 2·grass_cover.
struct ProceduralFeatureParams {
  Vec2 min_m{0.0f}, max_m{100.0f};
  float pixel_m = 2.0f;
  std::vector<int> tree_bits;
  int grass_types = 0;
  float patch_m = 40.0f;
  float tree_cover = 0.7f;
  float grass_cover = 0.8f;
  uint64_t seed = 1;
};
FeatureMap make_procedural_feature_map(const ProceduralFeatureParams& params);

}  // namespace sylva
