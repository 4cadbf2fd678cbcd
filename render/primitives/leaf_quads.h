#pragma once
// Leaf quads (Prototype::leaves: the leaves of meshed trees), in Prototype::leaf_material: one
// Embree quad each, cut to its outline (geometry/leaf_shape.h) by an alpha filter in both the
// closest-hit and the shadow query, so shadows see the cut-out.

#include "render/primitives/ray_hit.h"
#include "render/primitives/surface_hit.h"

namespace sylva {

class FlatWriter;

// Throws sylva::Error unless there are 4 corners per leaf and one stem index per leaf (or none).
void validate_leaf_quads(const Prototype& p);
// The box of the leaves' corners, object space (the outlines lie inside their quads).
Bounds3 leaf_quads_bounds(const Prototype& p);
// The hit point and geometric normal of a leaf hit (hit.u, hit.v its quad coordinates), object
// space; sets the context's material, uv, leaf flag and stem.
ObjectSurfaceHit decode_leaf_quad_hit(const Prototype& p, const RayHit& hit, HitContext& si);
// Writes the leaves of one copy into the flattened scene (render/primitives/flat_writer.h): each
// quad as triangles (0, 1, 2), (0, 2, 3) with its quad coordinates as uv, a part per outline.
void flatten_leaf_quads(const Prototype& p, FlatWriter& out);

}  // namespace sylva
