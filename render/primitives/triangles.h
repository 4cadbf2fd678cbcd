#pragma once
// Triangle meshes (Prototype::triangles: bark, ground, terrain, targets), in
// Prototype::triangle_material, optionally with vertex normals. Traced as Embree quads: consecutive
// triangles that share a diagonal are paired into one quad (triangles.cpp), which halves the
// primitives of a tube; a hit is decoded back to its triangle.

#include "render/primitives/ray_hit.h"
#include "render/primitives/surface_hit.h"

namespace sylva {

class FlatWriter;

// Throws sylva::Error when a triangle indexes a missing vertex.
void validate_triangles(const Prototype& p);
// The box of the mesh's vertices, object space.
Bounds3 triangles_bounds(const Prototype& p);
// The hit point and normals of a triangle hit (hit.u, hit.v its barycentrics of corners 2 and 3),
// object space; sets the context's material and uv.
ObjectSurfaceHit decode_triangle_hit(const Prototype& p, const RayHit& hit, HitContext& si);
// Writes the mesh of one copy into the flattened scene (render/primitives/flat_writer.h).
void flatten_triangles(const Prototype& p, FlatWriter& out);

}  // namespace sylva
