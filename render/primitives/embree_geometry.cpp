#include "render/primitives/embree_geometry.h"

#include "core/error.h"

namespace sylva {

static_assert(sizeof(Vec3) == 3 * sizeof(float), "a Vec3 array is an Embree FLOAT3 vertex buffer");

void EmbreePrototype::attach(RTCGeometry g, PrimitiveKind kind) {
  rtcCommitGeometry(g);
  const unsigned id = rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  if (id >= kPrimitiveKinds) throw Error("embree: unexpected geometry id");
  kind_of[id] = kind;
}

void attach_prototype(EmbreePrototype& e, const Prototype& p) {
  attach_triangles(e, p);
  attach_leaf_quads(e, p);
  attach_solids(e, p);
  attach_curves(e, p);
  attach_discs(e, p);
}

void set_quads(RTCGeometry g, const std::vector<glm::uvec4>& quads) {
  auto* idx = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), quads.size()));
  for (size_t i = 0; i < quads.size(); ++i)
    for (int k = 0; k < 4; ++k) idx[4 * i + k] = quads[i][k];
}

void set_vertices(RTCGeometry g, const std::vector<Vec3>& points) {
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), points.size()));
  for (size_t i = 0; i < points.size(); ++i) {
    v[3 * i] = points[i].x;
    v[3 * i + 1] = points[i].y;
    v[3 * i + 2] = points[i].z;
  }
}

size_t bind_vertices(RTCGeometry g, const std::vector<Vec3>& points) {
  if (points.capacity() <= points.size()) {
    set_vertices(g, points);
    return 0;
  }
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, points.data(), 0, sizeof(Vec3),
                             points.size());
  return points.size() * sizeof(Vec3);
}

}  // namespace sylva
