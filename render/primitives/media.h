#pragma once
// The turbid crowns (Fournier–Grindal crowns with optics = "turbid", docs/fournier_grindal.md):
// half-space solids (solids.h) with a leaf area density, media whose boundary a path crosses
// instead of being shaded there. What the integrator asks of them: whether a scene has any, whether
// a hit is on one, and what crossing it at that hit does to the path.

#include "render/primitives/ray_hit.h"
#include "render/scene.h"

namespace sylva {

// Whether any prototype of `scene` has a turbid crown.
bool has_turbid_crowns(const Scene& scene);

// The turbid crown `hit` is on, or nullptr (an opaque solid or another kind).
const HalfSpaceSolid* turbid_crown(const Scene& scene, const RayHit& hit);

// A path crossing a turbid crown's boundary at `hit` along `d` (unit): the boundary's unit world
// normal, outward; whether the path enters; the crown's extinction σ_t = G·LAD (the spherical
// leaf-angle G) and its leaf material (the first of its palette).
struct CrownCrossing {
  Vec3 normal{0.0f};
  bool entering = false;
  float sigma_t = 0.0f;
  uint32_t material = 0;
};
CrownCrossing cross_crown(const Scene& scene, const RayHit& hit, const HalfSpaceSolid& crown, const Vec3& d);

}  // namespace sylva
