#include "render/primitives/flat_writer.h"

#include "render/primitives/discs.h"
#include "render/primitives/leaf_quads.h"
#include "render/primitives/solids.h"
#include "render/primitives/triangles.h"

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

FlatWriter::FlatWriter(FlatScene* flat, bool normals, std::vector<TriangleMesh> prototype_meshes)
    : flat_(flat), normals_(normals), prototype_meshes_(std::move(prototype_meshes)) {}

void FlatWriter::start_instance(const Instance& inst) {
  world_from_object_ = inst.world_from_object;
  normal_from_object_ = glm::transpose(glm::inverse(Mat3(inst.world_from_object)));
}

void FlatWriter::add_vertex(const Vec3& p, const Vec3& world_normal, Vec2 uv) {
  ++vertices_;
  if (flat_ == nullptr) return;
  TriangleMesh& world = flat_->mesh;
  world.positions.push_back(Vec3(world_from_object_ * Vec4(p, 1.0f)));
  world.uvs.push_back(uv);
  if (normals_) world.normals.push_back(world_normal);
}

void FlatWriter::add_triangle(const glm::uvec3& t) {
  ++triangles_;
  if (flat_ != nullptr) flat_->mesh.triangles.push_back(t);
}

Vec3 FlatWriter::world_normal(const Vec3& n) const {
  const Vec3 w = normal_from_object_ * n;
  const float len = glm::length(w);
  return len > 0.0f ? w / len : Vec3(0.0f, 0.0f, 1.0f);
}

void FlatWriter::add_mesh(const TriangleMesh& mesh, uint32_t material) {
  const uint32_t base = next_vertex();
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    add_vertex(mesh.positions[i],
               mesh.normals.empty() || flat_ == nullptr ? Vec3(0.0f, 0.0f, 1.0f) : world_normal(mesh.normals[i]));
  for (const glm::uvec3& t : mesh.triangles) add_triangle(t + glm::uvec3(base));
  close_part({material, std::nullopt});
}

void FlatWriter::close_part(const FlatPart& part) {
  if (flat_ == nullptr) return;
  if (flat_->part.size() < flat_->mesh.triangles.size())
    flat_->part.resize(flat_->mesh.triangles.size(), part_index(flat_->parts, part));
}

void flatten_prototype(const Prototype& p, uint32_t prototype, FlatWriter& out) {
  flatten_triangles(p, out);
  flatten_leaf_quads(p, out);
  flatten_discs(p, out);
  flatten_solids(p, prototype, out);
}

}  // namespace sylva
