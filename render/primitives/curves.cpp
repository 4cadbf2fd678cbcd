#include "render/primitives/curves.h"

#include "core/error.h"
#include "geometry/grass.h"
#include "render/primitives/embree_geometry.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace sylva {

namespace {

// Embree curves (round lines at range, exact grass ribbons): a ray leaving one (offset along the normal by a
// few ulps) can re-hit it at t ≈ 0, since Embree's curve intersection is approximate at that scale;
// hits closer than this are rejected in both the intersection and the occlusion filter. 0.1 mm is
// below a line's width and above the re-hit distances (µm).
constexpr float kCurveMinDistance_m = 1e-4f;

void curve_near_filter(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    if (RTCRayN_tfar(args->ray, args->N, i) < kCurveMinDistance_m) args->valid[i] = 0;
  }
}

// Round curves (stems drawn as lines, geometry/trees/lod.h) as Embree's round Bézier tubes; exact
// ribbons as its normal-oriented Bézier curves.
RTCGeometry new_embree_curves(RTCDevice device, const CurveSet& cs) {
  RTCGeometry g = rtcNewGeometry(
      device, cs.round ? RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE : RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE);
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), cs.points.size()));
  auto* idx = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned), cs.size()));
  for (size_t i = 0; i < cs.points.size(); ++i)
    for (int k = 0; k < 4; ++k) v[4 * i + k] = cs.points[i][k];
  if (!cs.round) {
    auto* n = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), cs.normals.size()));
    for (size_t i = 0; i < cs.normals.size(); ++i)
      for (int k = 0; k < 3; ++k) n[3 * i + k] = cs.normals[i][k];
  }
  for (size_t i = 0; i < cs.size(); ++i) idx[i] = static_cast<unsigned>(4 * i);
  rtcSetGeometryIntersectFilterFunction(g, curve_near_filter);
  rtcSetGeometryOccludedFilterFunction(g, curve_near_filter);
  return g;
}

}  // namespace

void validate_curves(const Prototype& p) {
  const CurveSet& cs = p.curves;
  if (cs.size() == 0) return;
  if (cs.points.size() != 4 * cs.size() || cs.normals.size() != (cs.round ? 0 : cs.points.size()))
    throw Error(fmt::format("prototype '{}': curves need 4 control points each and, unless round, 4 normals", p.name));
}

Bounds3 curves_bounds(const Prototype& p) {
  Bounds3 b;
  float radius = 0.0f;
  for (const Vec4& v : p.curves.points) {
    b.extend(Vec3(v));
    radius = std::max(radius, std::abs(v.w));
  }
  if (b.empty()) return b;
  b.lo -= Vec3(radius);
  b.hi += Vec3(radius);
  return b;
}

void attach_curves(EmbreePrototype& e, const Prototype& p) {
  const CurveSet& cs = p.curves;
  if (cs.size() == 0) return;
  RTCGeometry g;
  if (cs.round || cs.exact) {
    g = new_embree_curves(e.device, cs);
  } else {
    // Ribbons (grass blades) as quad strips.
    std::vector<Vec3> points;
    std::vector<glm::uvec4> strips;
    tessellate_ribbons(cs, kRibbonSegments, points, strips);
    g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_QUAD);
    set_vertices(g, points);
    set_quads(g, strips);
    e.curve_strips = true;
  }
  e.attach(g, PrimitiveKind::kCurves);
  e.stats->curves += cs.size();
}

void decode_embree_curve_hit(const EmbreePrototype& e, unsigned prim, const Vec3& ng, RayHit* hit) {
  if (e.curve_strips) hit->primitive = prim / kRibbonSegments;
  hit->normal = ng;
}

void decode_curve_hit(const Ray& ray, const RayHit& hit, const Instance& inst, const Prototype& p, HitContext& si) {
  // A grass blade: a thin two-sided leaf (reflectance and transmittance) at the hit point.
  si.p = ray.origin + hit.t * ray.direction;
  si.material = p.curve_material;
  const Vec3 n = normal_from_object(inst) * hit.normal;
  const float ln = glm::length(n);
  si.ng = ln > 0 ? n / ln : -ray.direction;
  si.ns = si.ng;
}

}  // namespace sylva
