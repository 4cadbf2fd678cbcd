#pragma once
// The Embree 3 backend. Every rtc* call in Sylva lives in embree_scene.cpp (docs/design.md §6).
// One BVH per prototype (triangles and leaf quads as two geometries of one Embree scene), one
// single-level instance per placed copy. Leaf outlines are alpha masks applied in both the
// intersection and the occlusion filter, so shadows see the cut-out.

#include "render/scene.h"
#include "render/sensors/camera.h"
#include "render/testing/faults.h"

#include <cstdint>
#include <memory>

namespace sylva {

// A closest hit. `instance` indexes Scene::instances; `primitive` indexes the instance's
// prototype's triangles, or its leaf quads when `leaf` (then Prototype::leaves.stem[primitive], if
// present, is the tree stem carrying the leaf).
struct RayHit {
  float t = 0;
  uint32_t instance = 0;
  bool leaf = false;   // hit a leaf quad (else a triangle or a solid)
  bool solid = false;  // hit a solid: `primitive` indexes Prototype::solids
  uint32_t primitive = 0;
  float u = 0, v = 0;  // Embree's barycentrics (triangles) or quad coordinates (leaves)
  Vec3 normal{0.0f};   // solids: the unit outward normal in object space; curves: the ribbon's
                       // geometric normal in object space (not unit)
  bool curve = false;  // hit a curve: `primitive` indexes Prototype::curves
};

struct EmbreeStats {
  size_t bvh_bytes = 0;  // peak memory Embree reported through its memory monitor
  double build_ms = 0;
  size_t triangles = 0, leaf_quads = 0, instances = 0;  // unique geometry
  size_t solids = 0;
  size_t instanced_triangles = 0, instanced_leaf_quads = 0;
  size_t curves = 0, instanced_curves = 0;
};

class EmbreeScene {
 public:
  // Builds the BVHs, once: every pass over the scene (camera render, a light-view pass, a plot
  // sensor) shares them. `scene` must outlive this object (leaf shapes are read from it in
  // filters). Const member functions are safe to call from any number of threads.
  explicit EmbreeScene(const Scene& scene);
  // Test seam: the same scene with deliberate faults (render/testing/faults.h).
  EmbreeScene(const Scene& scene, const TransportFaults& faults);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Closest hit with t in [0, ray.t_max); false if none.
  bool intersect(const Ray& ray, RayHit* hit) const;
  // Any hit with t in [0, t_max).
  bool occluded(const Vec3& origin, const Vec3& direction, float t_max) const;

  const EmbreeStats& stats() const { return stats_; }
  // The scene the BVHs were built from.
  const Scene& scene() const { return *scene_; }

 private:
  const Scene* scene_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  EmbreeStats stats_;
};

}  // namespace sylva
