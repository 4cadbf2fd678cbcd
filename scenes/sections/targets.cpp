#include "scenes/sections/targets.h"

#include "geometry/mesh_io.h"

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <map>
#include <set>

namespace sylva {

namespace {

// One [[targets]] table as read.
struct TargetSpec {
  std::filesystem::path file;
  uint32_t material = 0;
  std::string label;
  Vec3 position{0.0f};
  float heading_deg = 0;
  float scale = 1;
  bool snap = true;

  // Translate to (x, y, z) · rotate by −heading about Z (a compass bearing turns clockwise) · scale.
  Mat4 world_from_object(float z) const {
    Mat4 m = glm::translate(Mat4(1.0f), Vec3(position.x, position.y, z));
    m = glm::rotate(m, -radians(heading_deg), Vec3(0, 0, 1));
    return glm::scale(m, Vec3(scale));
  }
};

TargetSpec read_target(const Params& t, const SceneBuilder& b) {
  t.check_keys({"name", "file", "material", "label", "position", "heading", "scale", "ground"});
  TargetSpec s;
  s.file = t.file_path("file");
  s.material = b.material_ref(t, "material");
  s.label = t.string("label");
  if (s.label.empty()) t.fail("label", "label must name the target's class, e.g. \"vehicle\"");
  if (!t.has("position")) t.fail("[[targets]] needs position = [x, y, z]");
  s.position = t.vec3("position", Vec3(0.0f));
  for (int i = 0; i < 3; ++i)
    if (!(std::abs(s.position[i]) <= kMaxSceneCoordinate_m))
      t.fail("position", fmt::format("position must lie within {:g} m of the origin", kMaxSceneCoordinate_m));
  s.heading_deg = t.real("heading", 0.0, -3600.0, 3600.0);
  s.scale = t.real("scale", 1.0, 1e-6, 1e6);
  const std::string ground = t.string("ground", "snap");
  if (ground != "snap" && ground != "none") t.fail("ground", "ground must be \"snap\" or \"none\"");
  s.snap = ground == "snap";
  return s;
}

// The ground targets snap onto: the [[meshes]] (classes `mesh_classes`) and terrain placed so far,
// collected on first use.
class Ground {
 public:
  Ground(const Scene& scene, const std::set<uint32_t>& mesh_classes) : scene_(scene), mesh_classes_(mesh_classes) {}

  // The highest surface on the vertical lines through the centre and the four corners of
  // `footprint` (x and y), or nullopt if none meets them.
  std::optional<float> height_under(const Bounds3& footprint) {
    if (!made_) {
      for (const Instance& inst : scene_.instances) {
        if (mesh_classes_.count(inst.class_id) == 0 && inst.class_id != kClassTerrain) continue;
        const TriangleMesh& mesh = scene_.prototypes[inst.prototype].triangles;
        if (mesh.triangles.empty()) continue;
        meshes_.push_back(PlacedMesh{&mesh, inst.world_from_object, placed_bounds(mesh, inst.world_from_object)});
        prototypes_.push_back(inst.prototype);
      }
      made_ = true;
    }
    // Targets add prototypes between calls, which may move the scene's prototype array.
    for (size_t i = 0; i < meshes_.size(); ++i) meshes_[i].mesh = &scene_.prototypes[prototypes_[i]].triangles;
    const Vec2 lo(footprint.lo), hi(footprint.hi);
    std::optional<float> best;
    for (const Vec2 xy : {(lo + hi) * 0.5f, lo, hi, Vec2(lo.x, hi.y), Vec2(hi.x, lo.y)}) {
      const std::optional<float> h = highest_surface_z(meshes_, xy);
      if (h && (!best || *h > *best)) best = h;
    }
    return best;
  }

 private:
  const Scene& scene_;
  const std::set<uint32_t>& mesh_classes_;
  std::vector<PlacedMesh> meshes_;
  std::vector<uint32_t> prototypes_;  // of meshes_[i]
  bool made_ = false;
};

// The prototype of a target's mesh with its material, read once per (file, material).
uint32_t target_prototype(const Params& t, const TargetSpec& s, const std::string& key, SceneBuilder& b,
                          std::map<std::string, uint32_t>& made) {
  auto it = made.find(key);
  if (it != made.end()) return it->second;
  Prototype p;
  p.name = s.file.filename().string();
  p.triangles = read_mesh(s.file);
  if (p.triangles.triangles.empty()) t.fail("file", s.file.string() + ": the mesh has no triangles");
  p.triangle_material = s.material;
  return made.emplace(key, b.scene().add_prototype(std::move(p))).first->second;
}

}  // namespace

void parse_targets(const Params& root, SceneBuilder& b) {
  std::map<std::string, uint32_t> prototypes;  // by (file, material)
  Ground ground(b.scene(), b.mesh_classes);
  for (const Params* t : root.tables("targets")) {
    const TargetSpec s = read_target(*t, b);
    const std::string key = fmt::format("{}|{}", s.file.string(), s.material);
    const uint32_t proto = target_prototype(*t, s, key, b, prototypes);
    const uint32_t class_id = b.class_of(s.label, *t, "label");
    const uint32_t variant_id =
        b.variant_of("target|" + key, {"target", b.scene().prototypes[proto].name, s.file.string(), 0, class_id});
    float z = s.position.z;
    if (s.snap) {
      const Bounds3 at_zero = placed_bounds(b.scene().prototypes[proto].triangles, s.world_from_object(0.0f));
      const std::optional<float> h = ground.height_under(at_zero);
      if (!h)
        t->fail("ground", fmt::format("nothing to snap to under the target at ({:g}, {:g}): no [[meshes]] or "
                                      "terrain there (or give ground = \"none\")",
                                      s.position.x, s.position.y));
      z = *h - at_zero.lo.z;
    }
    TargetInfo info;
    info.name = t->string("name", fmt::format("target{}", b.file().targets.size() + 1));
    info.instance = static_cast<uint32_t>(b.scene().instances.size());
    info.class_id = class_id;
    info.variant_id = variant_id;
    info.position = Vec3(s.position.x, s.position.y, z);
    info.heading_deg = s.heading_deg;
    b.scene().instances.push_back(Instance{proto, s.world_from_object(z), 1, class_id, variant_id});
    b.add_automatic_ids(info.instance, info.instance + 1);
    b.file().targets.push_back(std::move(info));
  }
}

}  // namespace sylva
