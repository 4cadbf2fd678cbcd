#pragma once
// Weber & Penn §5 level of detail in scene assembly (docs/lod.md): the `[lod]` settings, the
// level of a placed tree from its projected size, and the prototypes of one level. The level is
// chosen once per instance when the scene is built (not per ray), so camera, shadow and
// secondary rays all see the same geometry and shadows do not change with the ray.

#include "geometry/mesh.h"
#include "geometry/trees/lod.h"
#include "render/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sylva {

// [lod]: off unless the scene has a [lod] table (docs/scene_format.md). `bias` divides the
// calibrated range: 2 keeps full detail twice as far, 0.5 degrades at half the range.
struct LodSettings {
  bool enabled = false;
  float bias = 1.0f;
};

// The calibrated range r2 (geometry/trees/lod.h) of an object whose world bounds are `world`, seen
// by `camera` in an image of `width` × `height` pixels: the pixel footprint at the bounds' nearest
// point to the camera (0 inside them) for a perspective camera, the image's footprint per pixel
// for an orthographic one.
float instance_calibrated_range(const CameraDesc& camera, int width, int height, const Bounds3& world);

// The level for an instance (0 = full tree): lod_level_for(r2 / bias), or 0 when disabled.
int instance_lod_level(const LodSettings& settings, const CameraDesc& camera, int width, int height,
                       const Bounds3& world);

// One level's prototypes in the layout of the full tree's: bark (tubes and round-curve lines) with
// the leaf quads and discs of slot 0, one prototype per further leaf slot that has leaves, then the
// dead branches if any. materials = {bark, slot 0 leaf, slot 1, …} (the last slot takes every
// slot beyond it); prototypes without geometry are left out. `level` is consumed.
std::vector<Prototype> lod_prototypes(const std::string& name, TreeLod& level, const std::vector<uint32_t>& materials,
                                      uint32_t dead_material);

// What one level costs (`sylva tree --lod`): its drawn elements, leaf area, the bytes of its
// geometry as the Scene holds it, and the size of its BVH as Embree reports it (one prototype
// built alone, render/embree_scene.h).
struct LodLevelReport {
  float r2 = 0;
  LodCounts counts;
  size_t triangles = 0, leaf_quads = 0, curves = 0, discs = 0;
  double leaf_area_m2 = 0;  // one-sided, outlines included
  size_t geometry_bytes = 0;
  size_t bvh_bytes = 0;
  double build_ms = 0;
};
// Every level of kLodLevelR2 (level 0 as make_tree_lod at r2 = 0, the full tree) of a tree meshed
// as `mesh` with `options`, one after the other.
std::vector<LodLevelReport> report_lod_levels(const TreeModel& model, const TreeMesh& mesh,
                                              const TreeMeshOptions& options);

}  // namespace sylva
