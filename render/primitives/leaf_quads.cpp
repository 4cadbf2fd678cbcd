#include "render/primitives/leaf_quads.h"

#include "core/error.h"
#include "render/primitives/embree_geometry.h"
#include "render/primitives/flat_writer.h"

#include <fmt/core.h>

#include <algorithm>

namespace sylva {

namespace {

// Leaf alpha: reject hits outside the leaf outline (Weber & Penn §4.5 leaf shapes). A candidate the
// closest-hit query keeps may be the hit the integrator shades: its corners (and stem index) are
// fetched now, while Embree goes on traversing, instead of stalling Integrator::interaction
// (bench/README.md, "Memory stalls"). Shadow rays (kPrefetch false) never read them.
// kOval: every leaf of the geometry is oval (Weber & Penn's default), tested inline.
template <bool kPrefetch, bool kOval = false>
void leaf_alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto& data = *static_cast<const LeafFilterData*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned leaf = RTCHitN_primID(args->hit, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    bool inside;
    if constexpr (kOval)
      inside = inside_oval(u, v);
    else
      inside = leaf_shape_inside(data.one_shape ? data.shape : data.shapes[leaf], u, v);
    if (!inside) {
      args->valid[i] = 0;
    } else if constexpr (kPrefetch) {
      __builtin_prefetch(data.corners + 4 * size_t(leaf));
      __builtin_prefetch(data.corners + 4 * size_t(leaf) + 3);
      if (data.stems) __builtin_prefetch(data.stems + leaf);
    }
  }
}

}  // namespace

void validate_leaf_quads(const Prototype& p) {
  const LeafQuads& lq = p.leaves;
  if (lq.size() == 0) return;
  if (lq.corners.size() != 4 * lq.size())
    throw Error(fmt::format("prototype '{}': leaf quads need 4 corners per leaf", p.name));
  if (!lq.stem.empty() && lq.stem.size() != lq.size())
    throw Error(fmt::format("prototype '{}': leaf quads need one stem index per leaf (or none)", p.name));
}

Bounds3 leaf_quads_bounds(const Prototype& p) {
  Bounds3 b;
  for (const Vec3& v : p.leaves.corners) b.extend(v);
  return b;
}

void attach_leaf_quads(EmbreePrototype& e, const Prototype& p) {
  const LeafQuads& lq = p.leaves;
  if (lq.size() == 0) return;
  RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_QUAD);
  e.stats->shared_vertex_bytes += bind_vertices(g, lq.corners);
  auto* idx = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), lq.size()));
  for (size_t i = 0; i < 4 * lq.size(); ++i) idx[i] = static_cast<unsigned>(i);
  e.leaf_filter = std::make_unique<LeafFilterData>();
  LeafFilterData& filter = *e.leaf_filter;
  filter.shapes = lq.shapes.data();
  filter.corners = lq.corners.data();
  filter.stems = lq.stem.empty() ? nullptr : lq.stem.data();
  filter.one_shape = std::all_of(lq.shapes.begin(), lq.shapes.end(), [&](LeafShape s) { return s == lq.shapes[0]; });
  filter.shape = lq.shapes[0];
  rtcSetGeometryUserData(g, &filter);
  const bool oval = filter.one_shape && filter.shape == LeafShape::Oval;
  // Whole rectangles cut nothing: a shadow ray stops at the first without a callback (the
  // closest-hit filter stays, for its prefetch).
  const bool opaque = filter.one_shape && filter.shape == LeafShape::Rectangle;
  rtcSetGeometryIntersectFilterFunction(g, oval ? leaf_alpha_filter<true, true> : leaf_alpha_filter<true>);
  if (!e.no_shadow_alpha && !opaque)
    rtcSetGeometryOccludedFilterFunction(g, oval ? leaf_alpha_filter<false, true> : leaf_alpha_filter<false>);
  e.attach(g, PrimitiveKind::kLeafQuads);
  e.stats->leaf_quads += lq.size();
}

void flatten_leaf_quads(const Prototype& p, FlatWriter& out) {
  static constexpr Vec2 kCornerUv[4] = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  const LeafQuads& leaves = p.leaves;
  for (size_t q = 0; q < leaves.size(); ++q) {
    const uint32_t base = out.next_vertex();
    const Vec3* c = &leaves.corners[4 * q];
    const Vec3 n = out.world_normal(glm::cross(c[2] - c[0], c[3] - c[1]));
    for (int k = 0; k < 4; ++k) out.add_vertex(c[k], n, kCornerUv[k]);
    out.add_triangle({base, base + 1, base + 2});
    out.add_triangle({base, base + 2, base + 3});
    out.close_part({p.leaf_material, leaves.shapes[q]});
  }
}

ObjectSurfaceHit decode_leaf_quad_hit(const Prototype& p, const RayHit& hit, HitContext& si) {
  using namespace simd;
  const Vec3* c = &p.leaves.corners[4 * size_t(hit.primitive)];
  // Embree's quad parametrisation: triangle (c0,c1,c3) weighted (1−u−v, u, v) for u+v <= 1,
  // (c2,c3,c1) weighted (u+v−1, 1−u, 1−v) beyond. Which half a ray meets is random: the corners
  // and weights are selected, not branched on (the same arithmetic either way).
  const bool far = hit.u + hit.v > 1.0f;
  const __m128 a = load(far ? c[2] : c[0]);
  const __m128 b = load(far ? c[3] : c[1]);
  const __m128 d = load(far ? c[1] : c[3]);
  const float wa = select(far, hit.u + hit.v - 1.0f, 1.0f - hit.u - hit.v);
  const float wb = select(far, 1.0f - hit.u, hit.u), wd = select(far, 1.0f - hit.v, hit.v);
  ObjectSurfaceHit h;
  h.p = _mm_add_ps(_mm_add_ps(_mm_mul_ps(splat(wa), a), _mm_mul_ps(splat(wb), b)), _mm_mul_ps(splat(wd), d));
  h.ng = cross(_mm_sub_ps(b, a), _mm_sub_ps(d, a));
  h.ns = _mm_setzero_ps();
  si.material = p.leaf_material;
  si.uv = Vec2(hit.u, hit.v);  // Embree's quad coordinates are the leaf's (geometry/mesh.h)
  si.leaf = true;
  if (!p.leaves.stem.empty()) si.stem = p.leaves.stem[hit.primitive];
  return h;
}

}  // namespace sylva
