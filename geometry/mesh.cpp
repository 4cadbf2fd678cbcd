#include "geometry/mesh.h"

namespace sylva {

void append_mesh(TriangleMesh& dst, const TriangleMesh& src) {
  const bool dst_empty = dst.positions.empty();
  const bool keep_normals = (dst_empty || !dst.normals.empty()) && !src.normals.empty();
  const bool keep_uvs = (dst_empty || !dst.uvs.empty()) && !src.uvs.empty();
  const auto base = static_cast<uint32_t>(dst.positions.size());
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  if (keep_normals)
    dst.normals.insert(dst.normals.end(), src.normals.begin(), src.normals.end());
  else
    dst.normals.clear();
  if (keep_uvs)
    dst.uvs.insert(dst.uvs.end(), src.uvs.begin(), src.uvs.end());
  else
    dst.uvs.clear();
  dst.triangles.reserve(dst.triangles.size() + src.triangles.size());
  for (const glm::uvec3& t : src.triangles) dst.triangles.push_back(t + glm::uvec3(base));
}

Bounds3 transformed(const Bounds3& object, const Mat4& world_from_object) {
  Bounds3 world;
  if (object.empty()) return world;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1) ? object.hi.x : object.lo.x, (corner & 2) ? object.hi.y : object.lo.y,
                 (corner & 4) ? object.hi.z : object.lo.z);
    world.extend(Vec3(world_from_object * Vec4(p, 1.0f)));
  }
  return world;
}

Bounds3 bounds_of(const TreeMesh& mesh) {
  Bounds3 b;
  for (const Vec3& p : mesh.stems.positions) b.extend(p);
  for (const Vec3& p : mesh.dead_stems.positions) b.extend(p);
  for (const Vec3& p : mesh.leaves.corners) b.extend(p);
  return b;
}

float leaf_quad_area(const LeafQuads& leaves, size_t i) {
  const Vec3* c = &leaves.corners[4 * i];
  return 0.5f * (glm::length(glm::cross(c[1] - c[0], c[2] - c[0])) + glm::length(glm::cross(c[2] - c[0], c[3] - c[0])));
}

}  // namespace sylva
