#pragma once
// The Embree 3 backend. Every rtc* call in Sylva lives in embree_scene.cpp and, for each primitive
// kind's geometry, in that kind's file under render/primitives/ (docs/design.md §6).
// One BVH per prototype (triangles, leaf quads and grass ribbons as geometries of one Embree scene,
// all handed to Embree as triangles; round curves and discs as Embree curves and points); placed
// copies reach it either as one single-level Embree instance each, or — for many copies — as one
// "instance array": a user geometry whose primitive i is instance i, bounded by the instance's world
// box, intersected by moving the ray into the prototype's space and tracing the prototype's BVH
// (Scene::instance_level, kInstanceArrayThreshold; bench/README.md "Placed trees at scale"). Leaf
// outlines are alpha masks applied in both the intersection and the occlusion filter, so shadows
// see the cut-out. Leaf discs are Embree's
// normal-oriented disc points (RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT: the exact disc of a centre,
// radius and normal).
//
// A cyclic plot (PlotDesc::cyclic) makes the world periodic in x and y: every instance is placed
// nine times (shifted by −1, 0, +1 periods), and a ray is traced inside the plot's cell only — its
// origin wrapped into the cell, its segments clipped at the cell's side walls and continued from
// the opposite wall — so light leaving one side re-enters the other and none is lost.

#include "render/primitives/ray_hit.h"
#include "render/scene.h"
#include "render/sensors/camera.h"
#include "render/testing/faults.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sylva {

// No instance: a ray that leaves no surface (EmbreeScene::intersect's `from`).
inline constexpr uint32_t kNoInstance = 0xffffffffu;

// Embree instances (every copy of a cyclic plot counted) from which InstanceLevel::automatic uses
// the instance array. Below it, native instances: every golden scene has fewer, so their
// determinism hashes keep their tie order (docs/design.md §6 "Instance level").
inline constexpr size_t kInstanceArrayThreshold = 16384;

// Whether `scene` reaches Embree through the instance array (else one native instance per copy).
bool uses_instance_array(const Scene& scene);
// Whether `scene`'s copies are traced by the sweep (render/instance_sweep.h) instead of Embree's
// instance BVH: InstanceLevel::sweep, or automatic with at most InstanceBoxes::kMaxCopies Embree
// instances. Throws sylva::Error when the sweep is asked for more.
bool uses_instance_sweep(const Scene& scene);

// Bytes per Embree instance at the instance level beyond Scene::instances, measured
// (bench/README.md): native instances (Embree's geometry object, its transform, the top BVH) and
// the instance array (inverse transform, prototype index, the top BVH).
inline constexpr uint64_t kNativeInstanceBytes = 420;
inline constexpr uint64_t kArrayInstanceBytes = 150;

// The instruction set of Embree's traversal and intersection kernels: a cap (the processor's widest
// up to it), or kNative, the widest it has (Embree's own default). Each set's kernels round
// differently (AVX-512's from AVX2's, for a few rays in 10⁵), so a render's bits are the same on
// every machine that runs the same set, and its statistics the same everywhere. Sylva's default is
// kAvx2: the same bits on every x86-64 processor with AVX2, and on the forests measured the faster
// (AVX-512 traced a forest 4–5 % slower here, a small grove 3–4 % faster; bench/README.md, "Embree's
// instruction set"). The golden suite pins kAvx2 whatever a case asks (docs/design.md §6).
enum class EmbreeIsa { kNative, kSse2, kSse42, kAvx, kAvx2, kAvx512 };

// "native", "sse2", "sse4.2", "avx", "avx2", "avx512" (Embree's own names for its device option
// max_isa). parse_embree_isa throws sylva::Error naming them for anything else.
EmbreeIsa parse_embree_isa(const std::string& name);
const char* embree_isa_name(EmbreeIsa isa);
std::vector<std::string> embree_isa_names();  // every name parse_embree_isa takes (command lines' --isa)
// The set Embree runs on this processor for `requested`: the widest it has at most the cap
// (Embree's kernel choice: AVX-512 needs AVX-512 F, DQ, CD, BW and VL; AVX2 also FMA, BMI1 and BMI2).
EmbreeIsa resolve_embree_isa(EmbreeIsa requested);

struct EmbreeStats {
  EmbreeIsa isa = EmbreeIsa::kAvx2;  // the kernels in use (resolve_embree_isa), never kNative
  size_t bvh_bytes = 0;              // peak memory Embree reported through its memory monitor
  size_t shared_vertex_bytes = 0;    // the scene's vertex arrays Embree reads in place (not in bvh_bytes)
  double build_ms = 0;
  size_t triangles = 0, leaf_quads = 0, instances = 0;  // unique geometry
  size_t solids = 0, discs = 0;
  size_t instanced_triangles = 0, instanced_leaf_quads = 0;
  size_t curves = 0, instanced_curves = 0;
  bool instance_array = false;  // the instances reached Embree as one instance array
  bool instance_sweep = false;  // the copies are traced by the sweep, not Embree's instance BVH
};

// How much time the prototype BVHs' build may take. kThorough (Embree's high quality, with spatial
// splits where robust mode does not forbid them) traverses about 10 % faster than kFast (medium
// quality) but builds several times slower (bench/README.md): worth it when the render is long.
enum class BvhBuild { kFast, kThorough };

// The build worth choosing for a render of this many path samples (width · height · spp).
BvhBuild bvh_build_for(uint64_t path_samples);

class EmbreeScene {
 public:
  // Builds the BVHs, once: every pass over the scene (camera render, a light-view pass, a plot
  // sensor) shares them. `scene` must outlive this object and its prototypes' arrays keep their
  // storage (leaf shapes are read from them in filters; Embree reads their vertices in place).
  // Const member functions are safe to call from any number of threads.
  explicit EmbreeScene(const Scene& scene);
  // Test seam: the same scene with deliberate faults (render/testing/faults.h).
  EmbreeScene(const Scene& scene, const TransportFaults& faults);
  EmbreeScene(const Scene& scene, BvhBuild build, EmbreeIsa isa = EmbreeIsa::kAvx2);
  EmbreeScene(const Scene& scene, const TransportFaults& faults, BvhBuild build, EmbreeIsa isa = EmbreeIsa::kAvx2);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Closest hit with t in [0, ray.t_max); false if none. In a cyclic plot the hit point
  // ray.origin + t·direction and the point interpolated from the hit primitive may differ by whole
  // periods: both are the same point of the periodic world.
  // `from`: the instance (Scene::instances) whose surface the ray leaves, or kNoInstance. A hint
  // only: that instance is searched first, and in a scene of few instances a ray that ends inside
  // the instance's own box then skips the others (bench/README.md, "A sweep in place of the instance
  // BVH"). Any value gives the same hit, up to the order of exact ties.
  bool intersect(const Ray& ray, RayHit* hit, uint32_t from = kNoInstance) const;
  // Any hit with t in [0, t_max); `from` as for intersect.
  bool occluded(const Vec3& origin, const Vec3& direction, float t_max, uint32_t from = kNoInstance) const;

  const EmbreeStats& stats() const { return stats_; }
  // World bounds of all geometry (one period of a cyclic plot: the unshifted instances): the union
  // of every instance's prototype_bounds (render/primitives/primitive.h) through its transform,
  // padded by a few ulps, the boxes the label sidecar reports per object.
  const Bounds3& bounds() const { return bounds_; }
  // The scene the BVHs were built from.
  const Scene& scene() const { return *scene_; }

 private:
  const Scene* scene_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  EmbreeStats stats_;
  Bounds3 bounds_;

  void add_native_instances(const Scene& scene, int copies);
  void add_instance_array(const Scene& scene, int copies);
  void add_sweep(const Scene& scene, int copies);
  bool intersect_cell(const Ray& ray, RayHit* hit, uint32_t from) const;
  bool occluded_cell(const Vec3& origin, const Vec3& direction, float t_max, uint32_t from) const;
};

}  // namespace sylva
