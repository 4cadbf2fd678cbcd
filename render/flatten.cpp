// A scene flattened into one world-space triangle mesh (render/flatten.h).

#include "render/flatten.h"

#include "geometry/solids/solid_mesh.h"

#include <cmath>
#include <vector>

namespace sylva {

TriangleMesh flatten_scene(const Scene& scene) {
  size_t vertex_count = 0, triangle_count = 0;
  bool normals = true;
  for (const Instance& inst : scene.instances) {
    const Prototype& proto = scene.prototypes[inst.prototype];
    vertex_count +=
        proto.triangles.positions.size() + proto.leaves.corners.size() + (kFlattenedDiscSides + 1) * proto.discs.size();
    triangle_count += proto.triangles.triangles.size() + 2 * proto.leaves.size() + kFlattenedDiscSides * proto.discs.size();
    if (!proto.triangles.triangles.empty() && proto.triangles.normals.empty()) normals = false;
  }
  TriangleMesh world;
  std::vector<TriangleMesh> solid_meshes(scene.prototypes.size());
  world.positions.reserve(vertex_count);
  if (normals) world.normals.reserve(vertex_count);
  world.triangles.reserve(triangle_count);

  for (const Instance& inst : scene.instances) {
    const Prototype& proto = scene.prototypes[inst.prototype];
    const Mat4& m = inst.world_from_object;
    const Mat3 normal_from_object = glm::transpose(glm::inverse(Mat3(m)));
    auto to_world = [&](const Vec3& p) { return Vec3(m * Vec4(p, 1.0f)); };
    auto to_world_normal = [&](const Vec3& n) {
      const Vec3 w = normal_from_object * n;
      const float len = glm::length(w);
      return len > 0.0f ? w / len : Vec3(0.0f, 0.0f, 1.0f);
    };

    const TriangleMesh& tri = proto.triangles;
    auto base = static_cast<uint32_t>(world.positions.size());
    for (size_t i = 0; i < tri.positions.size(); ++i) {
      world.positions.push_back(to_world(tri.positions[i]));
      if (normals) world.normals.push_back(to_world_normal(tri.normals[i]));
    }
    for (const glm::uvec3& t : tri.triangles) world.triangles.push_back(t + glm::uvec3(base));

    const LeafQuads& leaves = proto.leaves;
    for (size_t q = 0; q < leaves.size(); ++q) {
      base = static_cast<uint32_t>(world.positions.size());
      Vec3 c[4];
      for (int k = 0; k < 4; ++k) c[k] = to_world(leaves.corners[4 * q + k]);
      const Vec3 n = glm::cross(c[2] - c[0], c[3] - c[1]);
      const float len = glm::length(n);
      for (int k = 0; k < 4; ++k) {
        world.positions.push_back(c[k]);
        if (normals) world.normals.push_back(len > 0.0f ? n / len : Vec3(0.0f, 0.0f, 1.0f));
      }
      world.triangles.push_back({base, base + 1, base + 2});
      world.triangles.push_back({base, base + 2, base + 3});
    }

    const LeafDiscs& discs = proto.discs;
    for (size_t d = 0; d < discs.size(); ++d) {
      base = static_cast<uint32_t>(world.positions.size());
      const Frame frame = Frame::from_z(discs.normal[d]);
      const Vec3 n = to_world_normal(discs.normal[d]);
      world.positions.push_back(to_world(discs.centre[d]));
      if (normals) world.normals.push_back(n);
      for (int k = 0; k < kFlattenedDiscSides; ++k) {
        const float a = kTwoPi * static_cast<float>(k) / kFlattenedDiscSides;
        world.positions.push_back(
            to_world(discs.centre[d] + discs.radius[d] * (std::cos(a) * frame.x + std::sin(a) * frame.y)));
        if (normals) world.normals.push_back(n);
      }
      for (uint32_t k = 0; k < kFlattenedDiscSides; ++k)
        world.triangles.push_back({base, base + 1 + k, base + 1 + (k + 1) % kFlattenedDiscSides});
    }

    // Half-space solids (Fournier–Grindal crowns and trunks), polygonised once per prototype.
    if (!proto.solids.empty()) {
      TriangleMesh& solid = solid_meshes[inst.prototype];
      if (solid.triangles.empty())
        for (const HalfSpaceSolid& s : proto.solids) append_mesh(solid, solid_surface_mesh(s));
      base = static_cast<uint32_t>(world.positions.size());
      for (size_t i = 0; i < solid.positions.size(); ++i) {
        world.positions.push_back(to_world(solid.positions[i]));
        if (normals) world.normals.push_back(to_world_normal(solid.normals[i]));
      }
      for (const glm::uvec3& t : solid.triangles) world.triangles.push_back(t + glm::uvec3(base));
    }
  }
  return world;
}

}  // namespace sylva
