#include "scenes/sections/meshes.h"

#include "geometry/mesh_io.h"
#include "geometry/primitives.h"

#include <fmt/core.h>

#include <iterator>
#include <string_view>
#include <utility>

namespace sylva {

namespace {

void make_plane_shape(const Params& t, Prototype& p) {
  const Vec2 size = t.vec2("size", Vec2(10.0f));
  p.triangles = make_plane(size.x, size.y, static_cast<int>(t.integer("tiles", 1, 1, 4096)));
}

void make_box_shape(const Params& t, Prototype& p) { p.triangles = make_box(t.vec3("size", Vec3(1.0f))); }

void make_sphere_shape(const Params& t, Prototype& p) {
  p.triangles = make_sphere(t.real("radius", 1.0, 1e-6, 1e6), static_cast<int>(t.integer("segments", 24, 3, 4096)));
}

void make_cylinder_shape(const Params& t, Prototype& p) {
  p.triangles = make_cylinder(t.real("radius", 0.1, 1e-6, 1e6), t.real("height", 1.0, 1e-6, 1e6),
                              static_cast<int>(t.integer("segments", 24, 3, 4096)));
}

void make_leaf_cloud_shape(const Params& t, Prototype& p) {
  LeafCloudParams lc;
  lc.radii = t.vec3("radii", lc.radii);
  lc.count = static_cast<int>(t.integer("count", lc.count, 1, 50'000'000));
  lc.leaf_length_m = t.real("leaf_length", lc.leaf_length_m, 1e-4, 10.0);
  lc.leaf_width_m = t.real("leaf_width", lc.leaf_width_m, 1e-4, 10.0);
  const std::string ls = t.string("leaf_shape", "oval");
  const auto shape_id = leaf_shape_from_name(ls);
  if (!shape_id) t.fail("leaf_shape", "unknown leaf_shape '" + ls + "'");
  lc.shape = *shape_id;
  p.leaves = make_leaf_cloud(lc, static_cast<uint64_t>(t.integer("seed", 1, 0, INT64_MAX)));
}

// The built-in shapes of [[meshes]], each reading its own keys. Adding a shape = one row here.
void make_shape(const Params& t, Prototype& p) {
  using Make = void (*)(const Params&, Prototype&);
  static constexpr std::pair<std::string_view, Make> kShapes[] = {
      {"plane", &make_plane_shape},           {"box", &make_box_shape},
      {"sphere", &make_sphere_shape},         {"cylinder", &make_cylinder_shape},
      {"leaf_cloud", &make_leaf_cloud_shape},
  };
  const std::string shape = t.has("shape") ? t.string("shape") : std::string();
  for (const auto& [name, make] : kShapes)
    if (name == shape) return make(t, p);
  std::string list;
  for (size_t i = 0; i < std::size(kShapes); ++i)
    list += (i == 0 ? "" : i + 1 == std::size(kShapes) ? " or " : ", ") + std::string(kShapes[i].first);
  t.fail("shape", "shape must be " + list + " (or give file = \"mesh.obj|ply\")");
}

}  // namespace

void parse_meshes(const Params& root, SceneBuilder& b) {
  for (const Params* t : root.tables("meshes")) {
    t->check_keys({"name",   "shape", "file",        "material",   "size",       "radius", "height", "segments",
                   "tiles",  "count", "leaf_length", "leaf_width", "leaf_shape", "seed",   "radii",  "translate",
                   "rotate", "scale", "object_id",   "instances",  "tile",       "class"});
    Prototype p;
    p.name = t->string("name", fmt::format("mesh{}", b.scene().prototypes.size()));
    const uint32_t material = b.material_ref(*t, "material");
    if (t->has("file")) {
      if (t->has("shape")) t->fail("give either shape or file, not both");
      p.triangles = read_mesh(t->file_path("file"));
      p.triangle_material = material;
    } else {
      make_shape(*t, p);
      (p.leaves.size() > 0 ? p.leaf_material : p.triangle_material) = material;
    }
    // A mesh names its class (a pad, a road, the ground) or is of class "mesh".
    const uint32_t class_id = t->has("class") ? b.class_of(t->string("class"), *t, "class") : kClassMesh;
    b.mesh_classes.insert(class_id);
    b.place(*t, b.scene().add_prototype(std::move(p)), class_id);
  }
}

}  // namespace sylva
