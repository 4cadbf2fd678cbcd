#pragma once
// Leaf discs (Prototype::discs: RAMI abstract canopies, [[leaves]] files), exact discs of a
// centre, radius and normal (Embree's normal-oriented disc points), two-sided in
// Prototype::disc_material, a leaf material; the normal gives the upper face.

#include "render/materials/hit_context.h"
#include "render/primitives/ray_hit.h"
#include "render/sensors/camera.h"

namespace sylva {

class FlatWriter;

// Throws sylva::Error unless every disc has a radius and a normal.
void validate_discs(const Prototype& p);
// The union of the discs' exact boxes: centre ± r·√(1 − n_a²) along each axis a (n unit).
Bounds3 discs_bounds(const Prototype& p);
// Fills the context of a disc's hit: the point on the world ray, the disc's normal as its upper side.
void decode_disc_hit(const Ray& ray, const RayHit& hit, const Instance& inst, const Prototype& p, HitContext& si);
// Writes the discs of one copy into the flattened scene (render/primitives/flat_writer.h): each a
// fan of kFlattenedDiscSides triangles inscribed in it (render/flatten.h).
void flatten_discs(const Prototype& p, FlatWriter& out);

}  // namespace sylva
