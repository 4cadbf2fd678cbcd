#pragma once
// Half-space solids (Prototype::solids: Fournier–Grindal crowns and trunks), intersected exactly
// as Embree user geometry (Fournier & Grindal §2.2, done per ray), each with a palette of
// materials its colouring picks from (Prototype::solid_palettes). A solid with a leaf area density
// is a turbid crown, a medium whose boundary is crossed rather than shaded (media.h).

#include "render/materials/hit_context.h"
#include "render/primitives/ray_hit.h"
#include "render/sensors/camera.h"

namespace sylva {

class FlatWriter;

// Throws sylva::Error unless every solid has a material palette.
void validate_solids(const Prototype& p);
// The union of the solids' bounds (HalfSpaceSolid::bounds: of every point of the solid).
Bounds3 solids_bounds(const Prototype& p);
// Fills the context of an opaque solid's hit: the point on the world ray, the normal, and the
// palette material its colouring picks at the point in the solid's own coordinates (§4).
void decode_solid_hit(const Ray& ray, const RayHit& hit, const Instance& inst, const Prototype& p, HitContext& si);
// Writes the solids of one copy (of prototype index `prototype`) into the flattened scene
// (render/primitives/flat_writer.h): polygonised once per prototype (geometry/solids/solid_mesh.h)
// in the first material of their palette.
void flatten_solids(const Prototype& p, uint32_t prototype, FlatWriter& out);

}  // namespace sylva
