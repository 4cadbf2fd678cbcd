#include "render/primitives/solids.h"

#include "core/error.h"
#include "geometry/solids/solid_mesh.h"
#include "render/primitives/embree_geometry.h"
#include "render/primitives/flat_writer.h"

#include <fmt/core.h>

#include <limits>

namespace sylva {

namespace {

// One primitive per solid; the ray arrives in the prototype's object space (Embree applies the
// instance transform).
void solid_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* solids = static_cast<const HalfSpaceSolid*>(args->geometryUserPtr);
  const Bounds3& b = solids[args->primID].bounds;
  *args->bounds_o = RTCBounds{b.lo.x, b.lo.y, b.lo.z, 0.0f, b.hi.x, b.hi.y, b.hi.z, 0.0f};
}

void solid_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto* solids = static_cast<const HalfSpaceSolid*>(args->geometryUserPtr);
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const Vec3 o(RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i), RTCRayN_org_z(ray, args->N, i));
    const Vec3 d(RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i), RTCRayN_dir_z(ray, args->N, i));
    SolidHit h;
    if (!intersect_solid(solids[args->primID], o, d, RTCRayN_tnear(ray, args->N, i), RTCRayN_tfar(ray, args->N, i), &h))
      continue;
    RTCRayN_tfar(ray, args->N, i) = h.t;
    RTCHitN_Ng_x(hit, args->N, i) = h.normal.x;
    RTCHitN_Ng_y(hit, args->N, i) = h.normal.y;
    RTCHitN_Ng_z(hit, args->N, i) = h.normal.z;
    RTCHitN_u(hit, args->N, i) = 0.0f;
    RTCHitN_v(hit, args->N, i) = 0.0f;
    RTCHitN_primID(hit, args->N, i) = args->primID;
    RTCHitN_geomID(hit, args->N, i) = args->geomID;
    for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l)
      RTCHitN_instID(hit, args->N, i, l) = args->context->instID[l];
  }
}

void solid_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto* solids = static_cast<const HalfSpaceSolid*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const Vec3 o(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                 RTCRayN_org_z(args->ray, args->N, i));
    const Vec3 d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                 RTCRayN_dir_z(args->ray, args->N, i));
    // A turbid crown does not block shadow rays: the integrator attenuates them by Beer's law.
    if (solids[args->primID].leaf_area_density > 0.0f) continue;
    SolidHit h;
    if (intersect_solid(solids[args->primID], o, d, RTCRayN_tnear(args->ray, args->N, i),
                        RTCRayN_tfar(args->ray, args->N, i), &h))
      RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
  }
}

}  // namespace

void validate_solids(const Prototype& p) {
  if (!p.solids.empty() && p.solid_palettes.size() != p.solids.size())
    throw Error(fmt::format("prototype '{}': every solid needs a material palette", p.name));
}

Bounds3 solids_bounds(const Prototype& p) {
  Bounds3 b;
  for (const HalfSpaceSolid& s : p.solids) b = merged(b, s.bounds);
  return b;
}

void attach_solids(EmbreePrototype& e, const Prototype& p) {
  if (p.solids.empty()) return;
  RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(p.solids.size()));
  rtcSetGeometryUserData(g, const_cast<HalfSpaceSolid*>(p.solids.data()));
  rtcSetGeometryBoundsFunction(g, solid_bounds, nullptr);
  rtcSetGeometryIntersectFunction(g, solid_intersect);
  rtcSetGeometryOccludedFunction(g, solid_occluded);
  e.attach(g, PrimitiveKind::kSolids);
  e.stats->solids += p.solids.size();
}

void flatten_solids(const Prototype& p, uint32_t prototype, FlatWriter& out) {
  if (p.solids.empty()) return;
  TriangleMesh& mesh = out.prototype_mesh(prototype);
  if (mesh.triangles.empty())
    for (const HalfSpaceSolid& s : p.solids) append_mesh(mesh, solid_surface_mesh(s));
  out.add_mesh(mesh, p.solid_palettes.front().front());
}

void decode_solid_hit(const Ray& ray, const RayHit& hit, const Instance& inst, const Prototype& p, HitContext& si) {
  si.p = ray.origin + hit.t * ray.direction;
  const Vec3 p_obj = Vec3(glm::inverse(inst.world_from_object) * Vec4(si.p, 1.0f));
  const std::vector<uint32_t>& palette = p.solid_palettes[hit.primitive];
  const HalfSpaceSolid& solid = p.solids[hit.primitive];
  si.material = palette[solid_palette_index(solid.colouring, p_obj, static_cast<uint32_t>(palette.size()))];
  si.ng = glm::normalize(normal_from_object(inst) * hit.normal);
  si.ns = si.ng;
}

}  // namespace sylva
