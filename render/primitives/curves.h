#pragma once
// Curves (Prototype::curves): thin two-sided ribbons (grass blades: cubic Bézier ribbons) in
// Prototype::curve_material, a leaf material, traced as strips of flat quads by default or as
// Embree's normal-oriented curves (CurveSet::exact); or round tubes (CurveSet::round: stems drawn as
// lines at range, geometry/trees/lod.h) in a bark material, Embree's round Bézier curves.

#include "render/materials/hit_context.h"
#include "render/primitives/ray_hit.h"
#include "render/sensors/camera.h"

namespace sylva {

// Grass ribbons reach Embree as strips of this many quads per blade (tessellate_ribbons): Embree's
// normal-oriented Bézier curves cost about 40 % of the default forest's render time, flat pieces a
// fraction of that, and six straight pieces follow a blade's arc to well under its width.
inline constexpr int kRibbonSegments = 6;

// Throws sylva::Error unless there are 4 control points per curve and, unless round, 4 normals.
void validate_curves(const Prototype& p);
// A box around every curve: its control points' box (a Bézier curve lies in their convex hull)
// grown by the largest radius (half-width) of any control point.
Bounds3 curves_bounds(const Prototype& p);
// Fills the context of a curve's hit: the point on the world ray, the ribbon's (or tube's) normal.
void decode_curve_hit(const Ray& ray, const RayHit& hit, const Instance& inst, const Prototype& p, HitContext& si);

}  // namespace sylva
