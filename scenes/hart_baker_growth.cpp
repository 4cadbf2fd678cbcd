#include "scenes/hart_baker_growth.h"

#include "core/hash.h"
#include "scenes/scene_file.h"

#include <cmath>

namespace sylva {

LightViewGeometry hart_baker_light_geometry(const HartBakerTree& tree, const HartBakerParams& params,
                                            const Vec3& to_light, const LightViewGeometry& obstacles) {
  LightViewGeometry g = obstacles;
  for (size_t i = 0; i < tree.size(); ++i) {
    if (!tree.alive[i]) continue;
    const Vec3 axis = tree.direction[i];
    Vec3 across = glm::cross(axis, to_light);
    // A limb seen end-on shows its base disc; any direction across it will do.
    across = glm::length(across) > 1e-6f ? glm::normalize(across) : Frame::from_z(axis).x;
    const Vec3 tip = tree.base[i] + axis * tree.length_m[i];
    const float R = tree.radius_m[i], r = tree.tip_radius(i, params);
    g.add_quad(tree.base[i] - across * R, tree.base[i] + across * R, tip + across * r, tip - across * r, -1);
  }
  // Leaves: the blade from the petiole end along frames.z, frames.x across (TreeLeaves).
  const TreeLeaves leaves = hart_baker_leaves(tree, params);
  for (size_t k = 0; k < leaves.size(); ++k) {
    const Vec3 p = leaves.positions[k];
    const Vec3 w = leaves.frames[k].x * (0.5f * leaves.width_m[k]);
    const Vec3 l = leaves.frames[k].z * leaves.length_m[k];
    g.add_quad(p - w, p + w, p + w + l, p - w + l, leaves.stem[k]);
  }
  return g;
}

LightWindow hart_baker_light_window(const HartBakerParams& params) {
  const float side = params.light.window_m;
  return LightWindow{Vec3(0.0f, 0.0f, 0.5f * side), side};
}

std::vector<float> hart_baker_light(const HartBakerTree& tree, const HartBakerParams& params,
                                    const LightViewGeometry& obstacles) {
  std::vector<float> light(tree.size(), 0.0f);
  const LightDirections directions{params.light.latitude_deg, params.light.first_day, params.light.last_day,
                                   params.light.sun_weight};
  const int samples = std::max(1, params.light.samples);
  for (int s = 0; s < samples; ++s) {
    const Vec3 to_light = sample_light_direction(
        directions, hash_ids(tree.seed, static_cast<uint64_t>(tree.year), static_cast<uint64_t>(s), 0x11947u));
    const LightView view = render_light_view(hart_baker_light_geometry(tree, params, to_light, obstacles), to_light,
                                             params.light.resolution, hart_baker_light_window(params));
    const std::vector<float> area = intercepted_area(view, tree.size());
    for (size_t i = 0; i < light.size(); ++i) light[i] += area[i] / static_cast<float>(samples);
  }
  return light;
}

void grow_hart_baker(HartBakerTree& tree, const HartBakerParams& params, int years, const LightViewGeometry& obstacles,
                     const GrowthCallback& after_year) {
  for (int y = 0; y < years; ++y) {
    const GrowthReport report = grow_hart_baker_year(tree, params, hart_baker_light(tree, params, obstacles));
    if (after_year) after_year(tree, report);
  }
}

HartBakerTree grow_hart_baker_tree(const HartBakerParams& params, uint64_t seed, int years,
                                   const LightViewGeometry& obstacles, const GrowthCallback& after_year) {
  HartBakerTree tree = make_hart_baker_seedling(params, seed);
  grow_hart_baker(tree, params, years, obstacles, after_year);
  return tree;
}

LightViewGeometry scene_obstacles(const std::filesystem::path& scene_file) {
  const SceneFile file = load_scene_file(scene_file);
  LightViewGeometry g;
  for (const Instance& instance : file.scene.instances) {
    const Prototype& p = file.scene.prototypes[instance.prototype];
    g.add_blockers(p.triangles, instance.world_from_object);
    g.add_blockers(p.leaves, instance.world_from_object);
  }
  return g;
}

}  // namespace sylva
