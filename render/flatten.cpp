// A scene flattened into one world-space triangle mesh (render/flatten.h).

#include "render/flatten.h"

#include "geometry/solids/solid_mesh.h"

#include <cmath>
#include <vector>

namespace sylva {

namespace {

// The row of `parts` holding `p`, added if new.
uint32_t part_index(std::vector<FlatPart>& parts, const FlatPart& p) {
  if (!parts.empty() && parts.back() == p) return static_cast<uint32_t>(parts.size() - 1);
  for (size_t i = 0; i < parts.size(); ++i)
    if (parts[i] == p) return static_cast<uint32_t>(i);
  parts.push_back(p);
  return static_cast<uint32_t>(parts.size() - 1);
}

}  // namespace

FlatScene flatten_scene(const Scene& scene) {
  size_t vertex_count = 0, triangle_count = 0;
  bool normals = true;
  for (const Instance& inst : scene.instances) {
    const Prototype& proto = scene.prototypes[inst.prototype];
    vertex_count +=
        proto.triangles.positions.size() + proto.leaves.corners.size() + (kFlattenedDiscSides + 1) * proto.discs.size();
    triangle_count +=
        proto.triangles.triangles.size() + 2 * proto.leaves.size() + kFlattenedDiscSides * proto.discs.size();
    if (!proto.triangles.triangles.empty() && proto.triangles.normals.empty()) normals = false;
  }
  FlatScene flat;
  TriangleMesh& world = flat.mesh;
  std::vector<TriangleMesh> solid_meshes(scene.prototypes.size());
  world.positions.reserve(vertex_count);
  world.uvs.reserve(vertex_count);
  if (normals) world.normals.reserve(vertex_count);
  world.triangles.reserve(triangle_count);
  flat.part.reserve(triangle_count);
  // Every triangle added since the last call is made of `part`.
  auto close_part = [&](const FlatPart& part) {
    if (flat.part.size() < world.triangles.size())
      flat.part.resize(world.triangles.size(), part_index(flat.parts, part));
  };

  for (const Instance& inst : scene.instances) {
    const Prototype& proto = scene.prototypes[inst.prototype];
    const Mat4& m = inst.world_from_object;
    const Mat3 normal_from_object = glm::transpose(glm::inverse(Mat3(m)));
    auto add_vertex = [&](const Vec3& p, const Vec3& world_normal, Vec2 uv = Vec2(0.0f)) {
      world.positions.push_back(Vec3(m * Vec4(p, 1.0f)));
      world.uvs.push_back(uv);
      if (normals) world.normals.push_back(world_normal);
    };
    auto to_world_normal = [&](const Vec3& n) {
      const Vec3 w = normal_from_object * n;
      const float len = glm::length(w);
      return len > 0.0f ? w / len : Vec3(0.0f, 0.0f, 1.0f);
    };
    auto add_mesh = [&](const TriangleMesh& mesh, uint32_t material) {
      const auto base = static_cast<uint32_t>(world.positions.size());
      for (size_t i = 0; i < mesh.positions.size(); ++i)
        add_vertex(mesh.positions[i], mesh.normals.empty() ? Vec3(0.0f, 0.0f, 1.0f) : to_world_normal(mesh.normals[i]));
      for (const glm::uvec3& t : mesh.triangles) world.triangles.push_back(t + glm::uvec3(base));
      close_part({material, std::nullopt});
    };

    add_mesh(proto.triangles, proto.triangle_material);

    const LeafQuads& leaves = proto.leaves;
    for (size_t q = 0; q < leaves.size(); ++q) {
      const auto base = static_cast<uint32_t>(world.positions.size());
      const Vec3* c = &leaves.corners[4 * q];
      const Vec3 n = to_world_normal(glm::cross(c[2] - c[0], c[3] - c[1]));
      static constexpr Vec2 kCornerUv[4] = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
      for (int k = 0; k < 4; ++k) add_vertex(c[k], n, kCornerUv[k]);
      world.triangles.push_back({base, base + 1, base + 2});
      world.triangles.push_back({base, base + 2, base + 3});
      close_part({proto.leaf_material, leaves.shapes[q]});
    }

    const LeafDiscs& discs = proto.discs;
    for (size_t d = 0; d < discs.size(); ++d) {
      const auto base = static_cast<uint32_t>(world.positions.size());
      const Frame frame = Frame::from_z(discs.normal[d]);
      const Vec3 n = to_world_normal(discs.normal[d]);
      add_vertex(discs.centre[d], n);
      for (int k = 0; k < kFlattenedDiscSides; ++k) {
        const float a = kTwoPi * static_cast<float>(k) / kFlattenedDiscSides;
        add_vertex(discs.centre[d] + discs.radius[d] * (std::cos(a) * frame.x + std::sin(a) * frame.y), n);
      }
      for (uint32_t k = 0; k < kFlattenedDiscSides; ++k)
        world.triangles.push_back({base, base + 1 + k, base + 1 + (k + 1) % kFlattenedDiscSides});
    }
    close_part({proto.disc_material, std::nullopt});

    // Half-space solids (Fournier–Grindal crowns and trunks), polygonised once per prototype.
    if (!proto.solids.empty()) {
      TriangleMesh& solid = solid_meshes[inst.prototype];
      if (solid.triangles.empty())
        for (const HalfSpaceSolid& s : proto.solids) append_mesh(solid, solid_surface_mesh(s));
      add_mesh(solid, proto.solid_palettes.front().front());
    }
  }
  return flat;
}

}  // namespace sylva
