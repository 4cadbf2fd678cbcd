#pragma once
// TreeModel → TreeMesh: bark tubes and leaf quads (docs/design.md §5). Pure and deterministic.

#include "geometry/mesh.h"
#include "geometry/trees/tree_model.h"

#include <array>

namespace sylva {

struct TreeMeshOptions {
  // Vertices around a stem per level (levels deeper than 3 use the last entry), before quality.
  std::array<int, 4> radial_segments = {16, 8, 5, 4};
  // Scales the radial resolution (Weber & Penn §4.5 quality factor); at least 3 around.
  float quality = 1.0f;
  bool leaves = true;
  // Mesh dead stems (TreeStems::dead) into TreeMesh::dead_stems instead of TreeMesh::stems. Off by
  // default so exports and geometry statistics see every stem in one mesh; scene assembly turns
  // it on to draw dead wood with its own material (docs/scene_format.md).
  bool split_dead_stems = false;
};

// Every stem becomes one closed tube (watertight on its own): a fan cap at its base, one ring per
// cross-section, and a single tip vertex when the stem tapers to a point (a fan cap otherwise).
// Rings are oriented along the bisector of the adjacent segments and their reference axis is
// parallel-transported along the stem, so a clone continues its twin's ring at the split point
// without twisting (§4.2). Trunk lobes (§4.4) shape the ring radii. Normals follow the surface
// slope; bark UVs: u = around (0..1, seam duplicated), v = distance along the stem divided by the
// stem's base circumference. Leaves become quads in the LeafQuads convention of geometry/mesh.h,
// in the model's leaf order, each keeping the index of its stem (LeafQuads::stem).
TreeMesh make_tree_mesh(const TreeModel& model, const TreeMeshOptions& options = {});

// Ring vertex count for a stem level under `options`.
int radial_segments_for_level(const TreeMeshOptions& options, int level, int lobes);

}  // namespace sylva
