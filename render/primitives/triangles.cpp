#include "render/primitives/triangles.h"

#include "core/error.h"
#include "render/primitives/embree_geometry.h"
#include "render/primitives/flat_writer.h"

#include <fmt/core.h>

namespace sylva {

namespace {

// Every prototype's surfaces reach Embree as one primitive type, quads, because Embree builds a
// BVH per primitive type in a scene and a ray would traverse each (bench/README.md, "One quad BVH
// per prototype"). A quad (q0, q1, q2, q3) is Embree's two triangles (q0, q1, q3) and (q2, q3, q1);
// a hit's (u, v) weigh q1 and q3 on the first half, and give (u+v−1)·q2 + (1−u)·q3 + (1−v)·q1 on the
// second. A leaf is one quad (c0, c1, c2, c3): (u, v) are its quad coordinates. A grass ribbon is
// a strip of quads. Mesh triangles are paired (MeshQuads).

// A triangle mesh as quads: consecutive triangles (a, b, c), (a, c, d) — a quad split along its
// diagonal a–c, as every mesher here emits them — become the one quad (b, c, d, a), whose halves
// (b, c, a) and (d, a, c) are the two triangles; any other triangle (a, b, c) becomes (a, b, c, c),
// whose second half is degenerate and never hit (Embree's triangle intersection, to the bit). The
// pairs halve the primitives of a tube. Unless `pair`, every triangle stays alone: the weight
// 1 − u − v of a paired hit is exact only to 6·10⁻⁸, which on a ground plane kilometres wide is
// millimetres (robust prototypes are not paired).
constexpr uint32_t kPairedQuad = 1u << 31;  // in MeshQuads::first: the quad holds two triangles

struct MeshQuads {
  std::vector<glm::uvec4> quads;
  std::vector<uint32_t> first;  // per quad: its first triangle, | kPairedQuad when it holds two
};

MeshQuads mesh_quads(const std::vector<glm::uvec3>& triangles, bool pair) {
  if (triangles.size() >= kPairedQuad)
    throw Error(fmt::format("{} triangles are too many for one mesh", triangles.size()));
  MeshQuads m;
  m.quads.reserve(triangles.size());
  m.first.reserve(triangles.size());
  for (size_t i = 0; i < triangles.size(); ++i) {
    const glm::uvec3 t = triangles[i];
    if (pair && i + 1 < triangles.size() && triangles[i + 1].x == t.x && triangles[i + 1].y == t.z) {
      m.quads.emplace_back(t.y, t.z, triangles[i + 1].z, t.x);
      m.first.push_back(static_cast<uint32_t>(i) | kPairedQuad);
      ++i;
    } else {
      m.quads.emplace_back(t.x, t.y, t.z, t.z);
      m.first.push_back(static_cast<uint32_t>(i));
    }
  }
  return m;
}

}  // namespace

void validate_triangles(const Prototype& p) {
  const TriangleMesh& tm = p.triangles;
  for (size_t i = 0; i < tm.triangles.size(); ++i) {
    const glm::uvec3 t = tm.triangles[i];
    if (t.x >= tm.positions.size() || t.y >= tm.positions.size() || t.z >= tm.positions.size())
      throw Error(fmt::format("prototype '{}': triangle {} indexes a missing vertex", p.name, i));
  }
}

Bounds3 triangles_bounds(const Prototype& p) {
  Bounds3 b;
  for (const Vec3& v : p.triangles.positions) b.extend(v);
  return b;
}

void attach_triangles(EmbreePrototype& e, const Prototype& p) {
  const TriangleMesh& tm = p.triangles;
  if (tm.triangles.empty()) return;
  MeshQuads mq = mesh_quads(tm.triangles, !e.robust);
  RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_QUAD);
  e.stats->shared_vertex_bytes += bind_vertices(g, tm.positions);
  set_quads(g, mq.quads);
  e.mesh_quad_first = std::move(mq.first);
  e.attach(g, PrimitiveKind::kTriangles);
  e.stats->triangles += tm.triangles.size();
}

void decode_embree_triangle_hit(const EmbreePrototype& e, unsigned prim, float u, float v, RayHit* hit) {
  // A hit (u, v) on a mesh quad whose MeshQuads::first is `first`: the triangle, and its
  // barycentrics b1, b2 (the weights of its second and third corners, as Embree's triangles give
  // them). (b, c, a) weighted (1−u−v, u, v) on the first half; (d, a, c) as above on the second.
  const uint32_t first = e.mesh_quad_first[prim];
  if (!(first & kPairedQuad)) {
    hit->primitive = first;
  } else if (u + v <= 1.0f) {
    hit->primitive = first & ~kPairedQuad;
    hit->u = 1.0f - u - v;
    hit->v = u;
  } else {
    hit->primitive = (first & ~kPairedQuad) + 1;
    hit->u = 1.0f - v;
    hit->v = u + v - 1.0f;
  }
}

void flatten_triangles(const Prototype& p, FlatWriter& out) { out.add_mesh(p.triangles, p.triangle_material); }

ObjectSurfaceHit decode_triangle_hit(const Prototype& p, const RayHit& hit, HitContext& si) {
  using namespace simd;
  const TriangleMesh& mesh = p.triangles;
  const glm::uvec3 t = mesh.triangles[hit.primitive];
  const __m128 b0 = splat(1.0f - hit.u - hit.v), b1 = splat(hit.u), b2 = splat(hit.v);
  const __m128 p0 = load(mesh.positions[t.x]), p1 = load(mesh.positions[t.y]), p2 = load(mesh.positions[t.z]);
  ObjectSurfaceHit h;
  h.p = _mm_add_ps(_mm_add_ps(_mm_mul_ps(b0, p0), _mm_mul_ps(b1, p1)), _mm_mul_ps(b2, p2));
  h.ng = cross(_mm_sub_ps(p1, p0), _mm_sub_ps(p2, p0));
  h.ns = _mm_setzero_ps();
  h.shading_normals = !mesh.normals.empty();
  if (h.shading_normals)
    h.ns = _mm_add_ps(_mm_add_ps(_mm_mul_ps(b0, load(mesh.normals[t.x])), _mm_mul_ps(b1, load(mesh.normals[t.y]))),
                      _mm_mul_ps(b2, load(mesh.normals[t.z])));
  si.material = p.triangle_material;
  si.uv = Vec2(hit.u, hit.v);
  return h;
}

}  // namespace sylva
