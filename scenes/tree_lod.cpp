#include "scenes/tree_lod.h"

#include "render/embree_scene.h"
#include "render/materials/diffuse.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>

namespace sylva {

float instance_calibrated_range(const CameraDesc& camera, int width, int height, const Bounds3& world) {
  const float footprint_m = std::visit(
      [&](const auto& p) -> float {
        if constexpr (std::is_same_v<std::decay_t<decltype(p)>, OrthographicProjection>) {
          return p.width_m / static_cast<float>(std::max(width, 1));
        } else {
          const Vec3 nearest = glm::clamp(camera.position, world.lo, world.hi);
          const float range_m = glm::length(nearest - camera.position);
          return range_m * 2.0f * std::tan(0.5f * radians(p.vfov_deg)) / static_cast<float>(std::max(height, 1));
        }
      },
      camera.projection);
  return lod_calibrated_range(footprint_m);
}

int instance_lod_level(const LodSettings& settings, const CameraDesc& camera, int width, int height,
                       const Bounds3& world) {
  if (!settings.enabled || world.empty()) return 0;
  return lod_level_for(instance_calibrated_range(camera, width, height, world) / settings.bias);
}

namespace {

// The quads and discs of leaf material slot `slot` (slots beyond `last` count as `last`).
void take_slot(const TreeLod& level, size_t slot, size_t last, Prototype& p) {
  const LeafQuads& quads = level.mesh.leaves;
  for (size_t i = 0; i < quads.size(); ++i) {
    if (std::min<size_t>(level.quad_slot[i], last) != slot) continue;
    p.leaves.corners.insert(p.leaves.corners.end(), quads.corners.begin() + static_cast<ptrdiff_t>(4 * i),
                            quads.corners.begin() + static_cast<ptrdiff_t>(4 * i + 4));
    p.leaves.shapes.push_back(quads.shapes[i]);
    if (!quads.stem.empty()) p.leaves.stem.push_back(quads.stem[i]);
  }
  for (size_t i = 0; i < level.discs.size(); ++i)
    if (std::min<size_t>(level.disc_slot[i], last) == slot)
      p.discs.add(level.discs.centre[i], level.discs.radius[i], level.discs.normal[i]);
}

bool has_geometry(const Prototype& p) {
  return !p.triangles.triangles.empty() || p.leaves.size() > 0 || p.curves.size() > 0 || p.discs.size() > 0;
}

}  // namespace

std::vector<Prototype> lod_prototypes(const std::string& name, TreeLod& level, const std::vector<uint32_t>& materials,
                                      uint32_t dead_material) {
  std::vector<Prototype> out;
  const std::string lod_name = fmt::format("{} (lod r2 {:g})", name, level.r2);
  const size_t last = materials.size() - 2;
  for (size_t slot = 0; slot + 1 < materials.size(); ++slot) {
    Prototype p;
    p.name = slot == 0 ? lod_name : fmt::format("{} (leaf material {})", lod_name, slot + 1);
    if (slot == 0) {
      p.triangles = std::move(level.mesh.stems);
      p.triangle_material = materials[0];
      p.curves = std::move(level.lines);
      p.curve_material = materials[0];
    }
    take_slot(level, slot, last, p);
    p.leaf_material = materials[slot + 1];
    p.disc_material = materials[slot + 1];
    if (has_geometry(p)) out.push_back(std::move(p));
  }
  Prototype dead;
  dead.name = lod_name + " (dead branches)";
  dead.triangles = std::move(level.mesh.dead_stems);
  dead.triangle_material = dead_material;
  dead.curves = std::move(level.dead_lines);
  dead.curve_material = dead_material;
  if (has_geometry(dead)) out.push_back(std::move(dead));
  level = TreeLod{};
  return out;
}

std::vector<LodLevelReport> report_lod_levels(const TreeModel& model, const TreeMesh& mesh,
                                              const TreeMeshOptions& options) {
  std::vector<LodLevelReport> out;
  for (const float r2 : kLodLevelR2) {
    TreeLod level = make_tree_lod(model, mesh, options, r2);
    LodLevelReport r;
    r.r2 = r2;
    r.counts = level.counts;
    r.leaf_area_m2 = leaf_outline_area(level.mesh.leaves) + level.discs.area();
    Scene scene;
    scene.add_material("grey", make_diffuse("grey", DenseSpectrum::constant(0.5f)));
    for (Prototype& p : lod_prototypes("tree", level, {0, 0}, 0)) {
      r.triangles += p.triangles.triangles.size();
      r.leaf_quads += p.leaves.size();
      r.curves += p.curves.size();
      r.discs += p.discs.size();
      r.geometry_bytes += p.triangles.positions.size() * sizeof(Vec3) + p.triangles.normals.size() * sizeof(Vec3) +
                          p.triangles.uvs.size() * sizeof(Vec2) + p.triangles.triangles.size() * sizeof(glm::uvec3) +
                          p.leaves.corners.size() * sizeof(Vec3) + p.leaves.shapes.size() * sizeof(LeafShape) +
                          p.leaves.stem.size() * sizeof(int32_t) + p.curves.points.size() * sizeof(Vec4) +
                          p.discs.size() * (2 * sizeof(Vec3) + sizeof(float));
      const uint32_t id = scene.add_prototype(std::move(p));
      scene.instances.push_back(Instance{id, Mat4(1.0f), 0, kClassMesh, 0});
    }
    const EmbreeScene embree(scene);
    r.bvh_bytes = embree.stats().bvh_bytes;
    r.build_ms = embree.stats().build_ms;
    out.push_back(r);
  }
  return out;
}

}  // namespace sylva
