#pragma once
// Summaries of a generated tree: counts, bounds, leaf area and a hash of the mesh, as printed by
// `sylva tree --stats` and stored as geometry goldens (golden/geometry/*.json).

#include "geometry/mesh.h"
#include "geometry/trees/tree_model.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sylva {

struct TreeStats {
  std::vector<int> stems_per_level;  // clones included
  std::vector<int> clones_per_level;
  int leaves = 0;
  size_t vertices = 0;
  size_t triangles = 0;
  size_t quads = 0;
  Bounds3 bounds;
  float height_m = 0;       // mesh bounding box height
  double leaf_area_m2 = 0;  // quad area, not counting the alpha cut-out
  uint64_t mesh_hash = 0;
};

// Hash of the mesh's exact bits (positions, normals, uvs, triangles, leaf corners and shapes). The
// leaves' stem indices are bookkeeping, not geometry, and are left out (golden/geometry hashes).
uint64_t hash_tree_mesh(const TreeMesh& mesh);

TreeStats compute_tree_stats(const TreeModel& model, const TreeMesh& mesh);

// Stems per level (index = level, clones included), the `stems_per_level` of TreeStats.
std::vector<int> count_stems_per_level(const TreeModel& model);

// One JSON object; `generation_ms` is included when given (not in goldens: it is not exact).
std::string tree_stats_json(const TreeStats& stats, const std::string& species, uint64_t seed,
                            std::optional<double> generation_ms = std::nullopt);

}  // namespace sylva
