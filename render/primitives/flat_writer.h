#pragma once
// What each primitive kind's flattener writes into (render/flatten.h: a scene as one world-space
// triangle mesh): the vertices and triangles of one placed copy at a time, moved to the world by its
// transform, and the part (material, outline) of the triangles added since the last part. Run
// twice by flatten_scene: first counting (no mesh: only the sizes, to reserve the arrays), then
// writing. Adding a kind: its flatten_<kind>(prototype, writer) and a line in flatten_prototype.

#include "render/flatten.h"

#include <utility>
#include <vector>

namespace sylva {

class FlatWriter {
 public:
  // Counts only when `flat` is null; `normals`: write a world normal per vertex; one (possibly
  // empty) prototype_mesh per prototype.
  FlatWriter(FlatScene* flat, bool normals, std::vector<TriangleMesh> prototype_meshes);

  // The copy the next vertices belong to.
  void start_instance(const Instance& inst);
  // The index the next vertex gets.
  uint32_t next_vertex() const { return static_cast<uint32_t>(vertices_); }
  // A vertex at object-space `p` with a world normal (ignored without normals) and uv.
  void add_vertex(const Vec3& p, const Vec3& world_normal, Vec2 uv = Vec2(0.0f));
  void add_triangle(const glm::uvec3& t);
  // An object-space normal in the world (normalised; +Z if it vanishes).
  Vec3 world_normal(const Vec3& n) const;
  // A whole object-space mesh (its normals to the world, +Z without), then its part.
  void add_mesh(const TriangleMesh& mesh, uint32_t material);
  // Every triangle added since the last call is made of `part`.
  void close_part(const FlatPart& part);
  // A per-prototype mesh a kind fills once and every copy reuses (polygonised solids).
  TriangleMesh& prototype_mesh(uint32_t prototype) { return prototype_meshes_[prototype]; }
  // Those meshes, handed on from the counting pass to the writing one.
  std::vector<TriangleMesh> take_prototype_meshes() { return std::move(prototype_meshes_); }

  size_t vertices() const { return vertices_; }
  size_t triangles() const { return triangles_; }

 private:
  FlatScene* flat_;
  bool normals_;
  size_t vertices_ = 0, triangles_ = 0;
  Mat4 world_from_object_{1.0f};
  Mat3 normal_from_object_{1.0f};
  std::vector<TriangleMesh> prototype_meshes_;
};

// The flattening of one copy of `p` (its instance started): each kind's flatten_<kind>, in
// PrimitiveKind order (curves are left out: render/flatten.h says why).
void flatten_prototype(const Prototype& p, uint32_t prototype, FlatWriter& out);

}  // namespace sylva
