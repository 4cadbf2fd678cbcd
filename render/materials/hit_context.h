#pragma once
// What a material sees of a hit: the world-space point and its frames, the surface coordinates,
// the ids of what was hit and the path's wavelengths. Built by the integrator's hit decoding
// (Integrator::interaction) as a flat struct; a material reads what it needs (today the face and
// the wavelengths; a texture lookup the uv and the ids).

#include "core/math.h"
#include "core/spectrum.h"

#include <cstdint>

namespace sylva {

struct HitContext {
  Vec3 p{0.0f};   // world space, m
  Vec3 ng{0.0f};  // geometric normal, unit; for leaves the upper (adaxial) side
  Vec3 ns{0.0f};  // shading normal, unit, on the same side as ng (the shading frame's z)
  // The hit's parametric coordinates: a mesh triangle's barycentrics (u, v) of its 2nd and 3rd
  // corners (a texture lookup maps them through TriangleMesh::uvs), a leaf quad's leaf coordinates
  // (geometry/mesh.h: u across the blade, v petiole to tip); (0, 0) on discs, curves and solids.
  Vec2 uv{0.0f};
  uint32_t material = 0;   // index into Scene::materials
  uint32_t instance = 0;   // index into Scene::instances
  uint32_t object_id = 0;  // the instance's object id (Instance::object_id)
  uint32_t prototype = 0;  // index into Scene::prototypes
  uint32_t primitive = 0;  // triangle, leaf quad, disc, curve or solid index within the prototype
  int32_t stem = -1;       // a tree leaf's stem in its tree model (TreeLeaves::stem); else -1
  bool leaf = false;       // a leaf quad or disc
  // Set by the integrator before the material is evaluated: whether the outgoing direction wo lies
  // on ng's side (the leaf's upper face), and the wavelengths the path carries.
  bool front = true;
  const SampledWavelengths* wl = nullptr;

  // The local shading frame the BSDF works in: z = ns turned to wo's side.
  Frame shading_frame() const { return Frame::from_z(front ? ns : -ns); }
};

}  // namespace sylva
