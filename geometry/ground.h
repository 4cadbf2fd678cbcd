#pragma once
// Ground queries for placing objects on whatever the scene stands on (targets snapped to the
// ground, docs/scene_format.md [[targets]]): where a vertical line meets placed triangle meshes.
// Any mesh works (a plane, a box, a terrain); no acceleration structure is built, so a query costs
// one pass over the triangles of the meshes whose world bounds contain the line.

#include "core/math.h"
#include "geometry/mesh.h"

#include <optional>
#include <vector>

namespace sylva {

// A triangle mesh placed in the world (not owned).
struct PlacedMesh {
  const TriangleMesh* mesh = nullptr;
  Mat4 world_from_object{1.0f};
  Bounds3 world_bounds;  // of the placed mesh (placed_bounds)
};

// The world bounds of `mesh` under an affine `world_from_object` (the transformed corners of its
// object-space box).
Bounds3 placed_bounds(const TriangleMesh& mesh, const Mat4& world_from_object);

// The world z of the highest point where the vertical line through (x, y) meets any triangle of
// `meshes` (edges and vertices included), or nullopt if it meets none. The line is intersected in
// each mesh's object space (Möller–Trumbore in double precision), so any affine placement works.
std::optional<float> highest_surface_z(const std::vector<PlacedMesh>& meshes, Vec2 xy);

}  // namespace sylva
