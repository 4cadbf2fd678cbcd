#include "geometry/placement.h"

#include "core/error.h"
#include "core/hash.h"
#include "core/rng.h"

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace sylva {

uint16_t FeatureMap::at(Vec2 xy) const {
  const Vec2 size = max_m - min_m;
  const float fx = (xy.x - min_m.x) / size.x * static_cast<float>(width);
  const float fy = (max_m.y - xy.y) / size.y * static_cast<float>(height);  // row 0 is the north edge
  if (!(fx >= 0.0f && fy >= 0.0f && fx < static_cast<float>(width) && fy < static_cast<float>(height))) return 0;
  return bits[static_cast<size_t>(fy) * static_cast<size_t>(width) + static_cast<size_t>(fx)];
}

std::vector<PlacedTree> place_trees(const FeatureMap& map, const HeightField& terrain,
                                    const std::vector<SpeciesPlacement>& species, uint64_t seed) {
  std::vector<PlacedTree> out;
  const Vec2 size = map.max_m - map.min_m;
  for (size_t s = 0; s < species.size(); ++s) {
    const SpeciesPlacement& sp = species[s];
    if (sp.bit < 0 || sp.bit >= kFeatureTreeBits) throw Error(fmt::format("feature bit {} is not 0–13", sp.bit));
    if (sp.trunk_radius_m.empty()) throw Error("a placed species needs at least one variant");
    if (!(sp.density_per_ha > 0.0) || !(sp.min_spacing_m > 0.0f)) continue;
    // Cells 2·spacing wide thinned to the density, or, for dense stands, one tree per cell of the
    // density's own spacing (which must exceed min_spacing to leave room to jitter).
    const double density_spacing = std::sqrt(1e4 / sp.density_per_ha);
    if (density_spacing <= sp.min_spacing_m)
      throw Error(fmt::format("a density of {:g} trees/ha cannot keep {:g} m apart (at most {:g} trees/ha)",
                              sp.density_per_ha, sp.min_spacing_m, 1e4 / (sp.min_spacing_m * sp.min_spacing_m)));
    const double cell = std::min(density_spacing, 2.0 * sp.min_spacing_m);
    const double keep = sp.density_per_ha * cell * cell / 1e4;
    const double jitter = cell - sp.min_spacing_m;
    const auto nx = static_cast<int64_t>(std::ceil(size.x / cell));
    const auto ny = static_cast<int64_t>(std::ceil(size.y / cell));
    if (nx * ny > (int64_t{1} << 34)) throw Error("a feature map's extent has too many placement cells");
    std::vector<std::vector<PlacedTree>> rows(static_cast<size_t>(ny));
    tbb::parallel_for(int64_t{0}, ny, [&](int64_t cy) {
      std::vector<PlacedTree>& row = rows[static_cast<size_t>(cy)];
      for (int64_t cx = 0; cx < nx; ++cx) {
        Pcg32 rng(hash_ids(seed, 0x7EE5, sp.bit, cx, cy));
        const double x = map.min_m.x + cx * cell + 0.5 * sp.min_spacing_m + jitter * rng.uniform_double();
        const double y = map.min_m.y + cy * cell + 0.5 * sp.min_spacing_m + jitter * rng.uniform_double();
        const bool kept = rng.uniform_double() < keep;
        const float heading = kTwoPi * rng.uniform();
        const float u_scale = rng.uniform();
        const uint32_t variant = rng.below(static_cast<uint32_t>(sp.trunk_radius_m.size()));
        const Vec2 xy(static_cast<float>(x), static_cast<float>(y));
        if (!kept || x >= map.max_m.x || y >= map.max_m.y || (map.at(xy) >> sp.bit & 1u) == 0) continue;
        PlacedTree t;
        t.scale = sp.scale_range.x + u_scale * (sp.scale_range.y - sp.scale_range.x);
        t.heading_rad = heading;
        t.species = static_cast<uint16_t>(s);
        t.variant = static_cast<uint16_t>(variant);
        t.base_m = Vec3(xy, terrain_min_height(terrain, xy, t.scale * sp.trunk_radius_m[variant]));
        row.push_back(t);
      }
    });
    for (const std::vector<PlacedTree>& row : rows) out.insert(out.end(), row.begin(), row.end());
  }
  return out;
}

std::vector<PlacedPatch> place_grass_patches(const FeatureMap& map, const HeightField& terrain,
                                             const std::vector<float>& patch_size_m, uint64_t seed) {
  std::vector<PlacedPatch> out;
  const Vec2 size = map.max_m - map.min_m;
  for (size_t t = 0; t < patch_size_m.size(); ++t) {
    const float cell = patch_size_m[t];
    if (!(cell > 0.0f)) continue;
    const auto nx = static_cast<int64_t>(std::ceil(size.x / cell));
    const auto ny = static_cast<int64_t>(std::ceil(size.y / cell));
    if (nx * ny > (int64_t{1} << 32)) throw Error("a feature map's extent has too many grass patches");
    std::vector<std::vector<PlacedPatch>> rows(static_cast<size_t>(ny));
    tbb::parallel_for(int64_t{0}, ny, [&](int64_t cy) {
      for (int64_t cx = 0; cx < nx; ++cx) {
        Pcg32 rng(hash_ids(seed, 0x6A55, t, cx, cy));
        const Vec2 jitter = symmetric2(rng);
        const Vec2 centre = map.min_m + cell * Vec2(static_cast<float>(cx) + 0.5f + 0.25f * jitter.x,
                                                    static_cast<float>(cy) + 0.5f + 0.25f * jitter.y);
        const float heading = kTwoPi * rng.uniform();
        if (centre.x >= map.max_m.x || centre.y >= map.max_m.y || grass_type(map.at(centre)) != static_cast<int>(t) + 1)
          continue;
        PlacedPatch p;
        p.grass_type = static_cast<int>(t) + 1;
        p.heading_rad = heading;
        const float h = 0.5f * cell;
        p.slope = Vec2(terrain_height(terrain, centre + Vec2(h, 0)) - terrain_height(terrain, centre - Vec2(h, 0)),
                       terrain_height(terrain, centre + Vec2(0, h)) - terrain_height(terrain, centre - Vec2(0, h))) /
                  cell;
        p.centre_m = Vec3(centre, terrain_height(terrain, centre));
        rows[static_cast<size_t>(cy)].push_back(p);
      }
    });
    for (const std::vector<PlacedPatch>& row : rows) out.insert(out.end(), row.begin(), row.end());
  }
  return out;
}

FeatureMap make_procedural_feature_map(const ProceduralFeatureParams& params) {
  FeatureMap map;
  map.min_m = params.min_m;
  map.max_m = params.max_m;
  map.width = std::max(1, static_cast<int>(std::ceil((params.max_m.x - params.min_m.x) / params.pixel_m)));
  map.height = std::max(1, static_cast<int>(std::ceil((params.max_m.y - params.min_m.y) / params.pixel_m)));
  map.bits.resize(static_cast<size_t>(map.width) * static_cast<size_t>(map.height));
  const Vec2 pixel = (map.max_m - map.min_m) / Vec2(static_cast<float>(map.width), static_cast<float>(map.height));
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const Vec2 p(map.min_m.x + (static_cast<float>(x) + 0.5f) * pixel.x,
                   map.max_m.y - (static_cast<float>(y) + 0.5f) * pixel.y);
      uint16_t v = 0;
      const float cover = 0.5f * (value_noise(hash_ids(params.seed, 0xC0FE), p / params.patch_m) + 1.0f);
      if (!params.tree_bits.empty() && cover < params.tree_cover) {
        // The species: the largest of one noise field per species, so stands have organic borders.
        size_t best = 0;
        float best_value = -2.0f;
        for (size_t s = 0; s < params.tree_bits.size(); ++s) {
          const float n = value_noise(hash_ids(params.seed, 0x5BEC, s), p / params.patch_m);
          if (n > best_value) best_value = n, best = s;
        }
        v |= static_cast<uint16_t>(1u << params.tree_bits[best]);
      }
      if (params.grass_types > 0) {
        const float g = value_noise(hash_ids(params.seed, 0x6A55), p / (0.5f * params.patch_m));
        if (g > 1.0f - 2.0f * params.grass_cover) {
          const float k = 0.5f * (value_noise(hash_ids(params.seed, 0x6A56), p / params.patch_m) + 1.0f);
          const int type =
              1 + std::min(params.grass_types - 1, static_cast<int>(k * static_cast<float>(params.grass_types)));
          v |= static_cast<uint16_t>(type << kFeatureGrassShift);
        }
      }
      map.bits[static_cast<size_t>(y) * static_cast<size_t>(map.width) + static_cast<size_t>(x)] = v;
    }
  return map;
}

}  // namespace sylva
