#include "render/primitives/discs.h"

#include "core/error.h"
#include "render/primitives/embree_geometry.h"
#include "render/primitives/flat_writer.h"

#include <fmt/core.h>

#include <cmath>

namespace sylva {

void validate_discs(const Prototype& p) {
  const LeafDiscs& discs = p.discs;
  if (discs.size() > 0 && (discs.radius.size() != discs.size() || discs.normal.size() != discs.size()))
    throw Error(fmt::format("prototype '{}': leaf discs need a radius and a normal each", p.name));
}

Bounds3 discs_bounds(const Prototype& p) {
  const LeafDiscs& discs = p.discs;
  Bounds3 b;
  for (size_t i = 0; i < discs.size(); ++i) {
    const float len2 = glm::dot(discs.normal[i], discs.normal[i]);
    const Vec3 n2 = len2 > 0 ? discs.normal[i] * discs.normal[i] / len2 : Vec3(0.0f);
    // A disc spans r·√(1 − n_a²) from its centre along axis a; rounded outwards by a few ulps.
    const Vec3 half = std::abs(discs.radius[i]) * glm::sqrt(glm::max(Vec3(1.0f) - n2, Vec3(0.0f))) * (1.0f + 1e-6f);
    b.extend(discs.centre[i] - half);
    b.extend(discs.centre[i] + half);
  }
  return b;
}

void attach_discs(EmbreePrototype& e, const Prototype& p) {
  const LeafDiscs& discs = p.discs;
  if (discs.size() == 0) return;
  RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT);
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), discs.size()));
  auto* n = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), discs.size()));
  for (size_t i = 0; i < discs.size(); ++i) {
    v[4 * i] = discs.centre[i].x;
    v[4 * i + 1] = discs.centre[i].y;
    v[4 * i + 2] = discs.centre[i].z;
    v[4 * i + 3] = discs.radius[i];
    n[3 * i] = discs.normal[i].x;
    n[3 * i + 1] = discs.normal[i].y;
    n[3 * i + 2] = discs.normal[i].z;
  }
  e.attach(g, PrimitiveKind::kDiscs);
  e.stats->discs += discs.size();
}

void flatten_discs(const Prototype& p, FlatWriter& out) {
  const LeafDiscs& discs = p.discs;
  for (size_t d = 0; d < discs.size(); ++d) {
    const uint32_t base = out.next_vertex();
    const Frame frame = Frame::from_z(discs.normal[d]);
    const Vec3 n = out.world_normal(discs.normal[d]);
    out.add_vertex(discs.centre[d], n);
    for (int k = 0; k < kFlattenedDiscSides; ++k) {
      const float a = kTwoPi * static_cast<float>(k) / kFlattenedDiscSides;
      out.add_vertex(discs.centre[d] + discs.radius[d] * (std::cos(a) * frame.x + std::sin(a) * frame.y), n);
    }
    for (uint32_t k = 0; k < kFlattenedDiscSides; ++k)
      out.add_triangle({base, base + 1 + k, base + 1 + (k + 1) % kFlattenedDiscSides});
  }
  out.close_part({p.disc_material, std::nullopt});
}

void decode_disc_hit(const Ray& ray, const RayHit& hit, const Instance& inst, const Prototype& p, HitContext& si) {
  si.p = ray.origin + hit.t * ray.direction;
  si.ng = glm::normalize(normal_from_object(inst) * p.discs.normal[hit.primitive]);
  si.ns = si.ng;
  si.material = p.disc_material;
  si.leaf = true;
}

}  // namespace sylva
