#include "render/primitives/media.h"

#include "render/materials/leaf_medium.h"

namespace sylva {

bool has_turbid_crowns(const Scene& scene) {
  for (const Prototype& p : scene.prototypes)
    for (const HalfSpaceSolid& solid : p.solids)
      if (solid.leaf_area_density > 0.0f) return true;
  return false;
}

const HalfSpaceSolid* turbid_crown(const Scene& scene, const RayHit& hit) {
  if (hit.kind != PrimitiveKind::kSolids) return nullptr;
  const HalfSpaceSolid& solid = scene.prototypes[scene.instances[hit.instance].prototype].solids[hit.primitive];
  return solid.leaf_area_density > 0.0f ? &solid : nullptr;
}

CrownCrossing cross_crown(const Scene& scene, const RayHit& hit, const HalfSpaceSolid& crown, const Vec3& d) {
  const Instance& inst = scene.instances[hit.instance];
  CrownCrossing c;
  // Unit, as offset_ray_origin expects: the normal matrix scales it by 1/scale for scaled crowns.
  c.normal = glm::normalize(normal_from_object(inst) * hit.normal);
  c.entering = glm::dot(d, c.normal) < 0.0f;
  c.sigma_t = kSphericalG * crown.leaf_area_density;
  c.material = scene.prototypes[inst.prototype].solid_palettes[hit.primitive].front();
  return c;
}

}  // namespace sylva
