#pragma once
// The Hart–Baker growth loop (seed 004 §4.1, §6.1): each year the tree is drawn from sampled sun
// and sky directions by the light-view rasterizer (render/light_view.h), the intercepted leaf area
// per limb becomes p_i of eq. 14, and the growth model (geometry/trees/hart_baker/) takes one step.
// The loop lives here so that neither library calls the other (docs/design.md §2).

#include "geometry/trees/hart_baker/hart_baker.h"
#include "render/light_view.h"

#include <filesystem>
#include <functional>
#include <vector>

namespace sylva {

// The light-view geometry of a tree seen from `to_light`: every leaf as a quad carrying its limb
// id, every living limb as its silhouette (a trapezoid from 2R to 2r facing the light) blocking,
// plus `obstacles` (blockers in tree space).
LightViewGeometry hart_baker_light_geometry(const HartBakerTree& tree, const HartBakerParams& params,
                                            const Vec3& to_light, const LightViewGeometry& obstacles);

// The light pass's window: with `[light] window_m` the face toward the light of a cube of that
// side standing on the ground around the trunk (§6.1's fixed aperture), else the crown's own
// bounding square.
LightWindow hart_baker_light_window(const HartBakerParams& params);

// p_i for the tree's current year: the intercepted leaf area (m²) per limb, averaged over
// params.light.samples directions drawn from hash_ids(tree.seed, tree.year, sample).
std::vector<float> hart_baker_light(const HartBakerTree& tree, const HartBakerParams& params,
                                    const LightViewGeometry& obstacles);

// Grows `years` more years, each with the light pass, which feeds eq. 14 (and so eq. 16–17) in
// every tree; params.phototropism decides whether the light also steers growth and shedding
// (off: the paper's "genetic" and "balanced" trees of Fig. 1).
// `after_year` (may be empty) sees the state and report after each year.
using GrowthCallback = std::function<void(const HartBakerTree&, const GrowthReport&)>;
void grow_hart_baker(HartBakerTree& tree, const HartBakerParams& params, int years, const LightViewGeometry& obstacles,
                     const GrowthCallback& after_year = {});

// A tree grown from the seedling for `years` years with `seed`.
HartBakerTree grow_hart_baker_tree(const HartBakerParams& params, uint64_t seed, int years,
                                   const LightViewGeometry& obstacles, const GrowthCallback& after_year = {});

// Everything a scene file places (meshes and trees, their leaves included) as blockers, in the
// scene's world frame, where the grown tree stands at the origin. Throws ParseError.
LightViewGeometry scene_obstacles(const std::filesystem::path& scene_file);

}  // namespace sylva
