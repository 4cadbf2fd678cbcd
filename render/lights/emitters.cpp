#include "render/lights/emitters.h"

#include <algorithm>
#include <cmath>

namespace sylva {

EmitterLights::EmitterLights(const Scene& scene) {
  // A cyclic plot's emitters are met by rays in all their periodic copies: not sampled (emitters.h).
  if (scene.plot.defined && scene.plot.cyclic) return;
  std::vector<float> weights;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Prototype& proto = scene.prototypes[inst.prototype];
    const TriangleMesh& mesh = proto.triangles;
    if (mesh.triangles.empty()) continue;
    const float power = emitted_power_w_m2(scene.materials[proto.triangle_material]);
    if (!(power > 0)) continue;
    first_.emplace_back(i, static_cast<uint32_t>(triangles_.size()));
    // The geometric normal a hit decodes (decode_triangle_hit, finish_surface_hit): the object
    // normal (p1 − p0) × (p2 − p0) through normal_from_object.
    const Mat3 normals = normal_from_object(inst);
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      const glm::uvec3 c = mesh.triangles[t];
      const Vec3 o0 = mesh.positions[c.x], o1 = mesh.positions[c.y], o2 = mesh.positions[c.z];
      Triangle tri;
      tri.p0 = Vec3(inst.world_from_object * Vec4(o0, 1.0f));
      tri.e1 = Vec3(inst.world_from_object * Vec4(o1, 1.0f)) - tri.p0;
      tri.e2 = Vec3(inst.world_from_object * Vec4(o2, 1.0f)) - tri.p0;
      const Vec3 n = normals * glm::cross(o1 - o0, o2 - o0);
      const float length = glm::length(n);
      tri.ng = length > 0 ? n / length : Vec3(0, 0, 1);
      tri.area = 0.5f * glm::length(glm::cross(tri.e1, tri.e2));
      tri.instance = i;
      tri.primitive = t;
      tri.material = proto.triangle_material;
      tri.object_id = inst.object_id;
      tri.prototype = inst.prototype;
      triangles_.push_back(tri);
      weights.push_back(std::isfinite(tri.area) ? tri.area * power : 0.0f);
    }
  }
  double total = 0;
  for (const float w : weights) total += w;
  if (!(total > 0)) {
    triangles_.clear();
    first_.clear();
    return;
  }
  distribution_ = Distribution1D(weights);
}

EmitterPoint EmitterLights::sample(float u_select, Vec2 u) const {
  float pdf = 0;
  int bin = 0;
  distribution_.sample(u_select, &pdf, &bin);
  const Triangle& tri = triangles_[static_cast<size_t>(bin)];
  // pbrt-v4's SampleUniformTriangle: barycentrics (b0, b1, b2) uniform over the triangle.
  float b0 = 0, b1 = 0;
  if (u.x < u.y) {
    b0 = u.x / 2;
    b1 = u.y - b0;
  } else {
    b1 = u.y / 2;
    b0 = u.x - b1;
  }
  const float b2 = 1.0f - b0 - b1;
  EmitterPoint e;
  e.ctx.p = tri.p0 + b1 * tri.e1 + b2 * tri.e2;
  e.ctx.ng = tri.ng;
  e.ctx.ns = tri.ng;
  e.ctx.uv = Vec2(b1, b2);
  e.ctx.material = tri.material;
  e.ctx.instance = tri.instance;
  e.ctx.object_id = tri.object_id;
  e.ctx.prototype = tri.prototype;
  e.ctx.primitive = tri.primitive;
  e.pdf_area = tri.area > 0 ? pdf / static_cast<float>(distribution_.size()) / tri.area : 0.0f;
  return e;
}

float EmitterLights::pdf_area(const RayHit& hit) const {
  if (hit.kind != PrimitiveKind::kTriangles) return 0.0f;
  const auto it = std::lower_bound(first_.begin(), first_.end(), std::make_pair(hit.instance, 0u));
  if (it == first_.end() || it->first != hit.instance) return 0.0f;
  const size_t index = it->second + static_cast<size_t>(hit.primitive);
  const Triangle& tri = triangles_[index];
  if (!(tri.area > 0)) return 0.0f;
  return distribution_.bin_pdf(static_cast<int>(index)) / static_cast<float>(distribution_.size()) / tri.area;
}

}  // namespace sylva
