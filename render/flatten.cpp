// A scene flattened into one world-space triangle mesh (render/flatten.h): every copy of every
// prototype through its kinds' flatteners (render/primitives/flat_writer.h).

#include "render/flatten.h"

#include "render/primitives/flat_writer.h"

namespace sylva {

namespace {

void flatten_instances(const Scene& scene, FlatWriter& out) {
  for (const Instance& inst : scene.instances) {
    out.start_instance(inst);
    flatten_prototype(scene.prototypes[inst.prototype], inst.prototype, out);
  }
}

}  // namespace

FlatScene flatten_scene(const Scene& scene) {
  // Vertex normals only when every mesh has them.
  bool normals = true;
  for (const Instance& inst : scene.instances) {
    const Prototype& proto = scene.prototypes[inst.prototype];
    if (!proto.triangles.triangles.empty() && proto.triangles.normals.empty()) normals = false;
  }
  // First the sizes, then the mesh in arrays of that size.
  FlatWriter count(nullptr, normals, std::vector<TriangleMesh>(scene.prototypes.size()));
  flatten_instances(scene, count);
  FlatScene flat;
  TriangleMesh& world = flat.mesh;
  world.positions.reserve(count.vertices());
  world.uvs.reserve(count.vertices());
  if (normals) world.normals.reserve(count.vertices());
  world.triangles.reserve(count.triangles());
  flat.part.reserve(count.triangles());
  FlatWriter out(&flat, normals, count.take_prototype_meshes());
  flatten_instances(scene, out);
  return flat;
}

}  // namespace sylva
