#include "render/embree_scene.h"

#include "core/error.h"
#include "render/cell_walk.h"
#include "render/instance_sweep.h"
#include "render/primitives/embree_geometry.h"
#include "render/primitives/leaf_quads.h"
#include "render/primitives/primitive.h"
#include "render/primitives/triangles.h"

#include <embree3/rtcore.h>
#include <fmt/core.h>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>

namespace sylva {

namespace {

// Robust mode keeps grazing hits on large triangles (a ground plane to the horizon, a terrain)
// watertight; it costs about 15 % of the traversal (bench/README.md), so it is set only where the
// geometry is that large: a prototype wider than this. Trees, grass and targets are traced in
// Embree's fast mode, where a ray through a shared edge of their small triangles can, very rarely,
// slip through.
constexpr float kRobustExtent_m = 100.0f;

// Per prototype: whether any placed copy of its triangles and leaves is wider than kRobustExtent_m
// in world space (a plane may be a unit square scaled by its instance).
std::vector<bool> robust_prototypes(const Scene& scene) {
  std::vector<Bounds3> object(scene.prototypes.size());
  for (size_t p = 0; p < scene.prototypes.size(); ++p)
    object[p] = merged(triangles_bounds(scene.prototypes[p]), leaf_quads_bounds(scene.prototypes[p]));
  std::vector<bool> robust(scene.prototypes.size(), false);
  for (const Instance& inst : scene.instances) {
    if (inst.prototype >= object.size() || robust[inst.prototype] || object[inst.prototype].empty()) continue;
    const Bounds3 b = transformed(object[inst.prototype], inst.world_from_object);
    const Vec3 extent = b.hi - b.lo;
    robust[inst.prototype] = std::max({extent.x, extent.y, extent.z}) > kRobustExtent_m;
  }
  return robust;
}

void error_callback(void*, RTCError code, const char* message) {
  // Embree reports API misuse here; surface it as an exception at the next check.
  fmt::print(stderr, "sylva: embree error {}: {}\n", static_cast<int>(code), message ? message : "");
}

// The nine cells of a cyclic plot's neighbourhood, in periods; the plot's own cell first.
const Vec2 kCellShifts[9] = {{0, 0}, {-1, -1}, {0, -1}, {1, -1}, {-1, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}};

// The instance array (InstanceLevel::array): one user geometry over every placed copy. Primitive p
// is copy k = p / count of instance i = p % count — the ids native instances would have — so a hit's
// instID[0] means the same on both paths. A ray reaches an instance's prototype as through Embree's
// own instances: origin and direction moved into object space by the inverse transform and not
// renormalised, so every distance (tnear, tfar, the hit's t) is the same number in world and object
// units, whatever the instance's scale; the prototype's filters (leaf outlines, the curve near-hit
// filter) run inside its own BVH. Per instance nothing is stored beyond Scene::instances: the inverse
// is computed per visit (as fast as a stored one, measured: bench_placements.cpp), which saves 48
// bytes per instance.
struct InstanceArray {
  const Instance* instances = nullptr;
  const RTCScene* prototypes = nullptr;       // per prototype
  const Bounds3* prototype_bounds = nullptr;  // per prototype, object space
  uint32_t count = 0;                         // instances (one period)
  Vec2 period{0.0f};
};

// An instance's world box, copy `k`: its prototype's object box through the transform, widened by
// a few ulps of its coordinates so that rounding in the corners' transform cannot cut off a hit
// found in object space. Empty (inverted, which Embree leaves out) for an empty prototype or a
// singular transform (a copy flattened to nothing).
Bounds3 array_instance_bounds(const InstanceArray& a, uint32_t i, uint32_t k) {
  const Instance& inst = a.instances[i];
  if (glm::determinant(Mat3(inst.world_from_object)) == 0.0f) return Bounds3{};
  Bounds3 b = transformed(a.prototype_bounds[inst.prototype], inst.world_from_object);
  if (b.empty()) return b;
  const Vec2 shift = kCellShifts[k] * a.period;
  b.lo += Vec3(shift, 0.0f);
  b.hi += Vec3(shift, 0.0f);
  const Vec3 pad = 4.0f * std::numeric_limits<float>::epsilon() * glm::max(glm::abs(b.lo), glm::abs(b.hi));
  b.lo -= pad;
  b.hi += pad;
  return b;
}

void array_bounds(const RTCBoundsFunctionArguments* args) {
  const auto& a = *static_cast<const InstanceArray*>(args->geometryUserPtr);
  const Bounds3 b = array_instance_bounds(a, args->primID % a.count, args->primID / a.count);
  *args->bounds_o = RTCBounds{b.lo.x, b.lo.y, b.lo.z, 0.0f, b.hi.x, b.hi.y, b.hi.z, 0.0f};
}

// The Embree ray from `o` along `d` over [tnear, tfar] at `time` with `mask`, written in place with
// three 16-byte stores, the width in which Embree loads it: a ray built elsewhere and copied, or
// stored a field at a time, is read back in 16-byte loads of 4-byte stores, which the processor
// cannot forward (a stall per ray, 1-2 % of a render).
void set_rtc_ray(RTCRay& r, const Vec3& o, const Vec3& d, float tnear, float tfar, float time = 0.0f,
                 unsigned mask = 0xffffffffu) {
  static_assert(sizeof(RTCRay) == 48 && alignof(RTCRay) == 16);
#if defined(__SSE2__)
  _mm_store_ps(&r.org_x, _mm_setr_ps(o.x, o.y, o.z, tnear));
  _mm_store_ps(&r.dir_x, _mm_setr_ps(d.x, d.y, d.z, time));
  _mm_store_si128(reinterpret_cast<__m128i*>(&r.tfar),
                  _mm_setr_epi32(std::bit_cast<int>(tfar), static_cast<int>(mask), 0, 0));  // id 0, flags 0
#else
  r = RTCRay{o.x, o.y, o.z, tnear, d.x, d.y, d.z, time, tfar, mask, 0, 0};
#endif
}

// Copy `copy` of instance `inst` (kCellShifts[copy] periods away): the inverse of its linear part
// and its world origin, which move a ray into its object space (set_object_ray).
struct CopyFrame {
  Mat3 object_from_world;
  Vec3 origin;
};
CopyFrame copy_frame(const Instance& inst, uint32_t copy, Vec2 period) {
  const Mat4& world_from_object = inst.world_from_object;
  return {glm::inverse(Mat3(world_from_object)), Vec3(world_from_object[3]) + Vec3(kCellShifts[copy] * period, 0.0f)};
}

// The world ray o + t·d moved into a copy's object space, written into `r`: the origin relative to
// the copy's own origin first, then turned and scaled (the subtraction cancels the large world
// coordinates before any rounding of a product); the direction not renormalised, so t means the
// same in both spaces.
void set_object_ray(RTCRay& r, const CopyFrame& f, const Vec3& o, const Vec3& d, float tnear, float tfar,
                    float time = 0.0f, unsigned mask = 0xffffffffu) {
  set_rtc_ray(r, f.object_from_world * (o - f.origin), f.object_from_world * d, tnear, tfar, time, mask);
}

// Ray `j` of `rays` moved into the object space of array primitive `prim`, written into `r`.
void set_array_object_ray(RTCRay& r, const InstanceArray& a, unsigned prim, RTCRayN* rays, unsigned n, unsigned j) {
  const Vec3 o(RTCRayN_org_x(rays, n, j), RTCRayN_org_y(rays, n, j), RTCRayN_org_z(rays, n, j));
  const Vec3 d(RTCRayN_dir_x(rays, n, j), RTCRayN_dir_y(rays, n, j), RTCRayN_dir_z(rays, n, j));
  set_object_ray(r, copy_frame(a.instances[prim % a.count], prim / a.count, a.period), o, d, RTCRayN_tnear(rays, n, j),
                 RTCRayN_tfar(rays, n, j), RTCRayN_time(rays, n, j), RTCRayN_mask(rays, n, j));
}

void array_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto& a = *static_cast<const InstanceArray*>(args->geometryUserPtr);
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
  RTCScene prototype = a.prototypes[a.instances[args->primID % a.count].prototype];
  for (unsigned j = 0; j < args->N; ++j) {
    if (args->valid[j] != -1) continue;
    RTCRayHit rh;  // Embree reads only the ray and the hit's ids
    set_array_object_ray(rh.ray, a, args->primID, rays, args->N, j);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l) rh.hit.instID[l] = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(prototype, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    RTCRayN_tfar(rays, args->N, j) = rh.ray.tfar;
    rh.hit.instID[0] = args->primID;
    rtcCopyHitToHitN(hits, &rh.hit, args->N, j);
  }
}

void array_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto& a = *static_cast<const InstanceArray*>(args->geometryUserPtr);
  RTCScene prototype = a.prototypes[a.instances[args->primID % a.count].prototype];
  for (unsigned j = 0; j < args->N; ++j) {
    if (args->valid[j] != -1) continue;
    RTCRay r;
    set_array_object_ray(r, a, args->primID, args->ray, args->N, j);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded1(prototype, &context, &r);
    if (r.tfar < 0.0f) RTCRayN_tfar(args->ray, args->N, j) = -std::numeric_limits<float>::infinity();
  }
}

// The sweep (render/instance_sweep.h): a scene of at most InstanceBoxes::kMaxCopies copies traced
// without Embree's instance BVH. Each copy as the sweep enters it: its frame (the ray moved into its
// object space as for the instance array) and its prototype's BVH.
struct SweepCopy {
  CopyFrame frame;
  RTCScene prototype = nullptr;
  unsigned id = 0;  // the Embree instance id it stands for: copy k of instance i is k·N + i
};

struct InstanceSweep {
  std::vector<SweepCopy> copies;
  InstanceBoxes boxes;  // copy j's world box is box j
};

// Copy `c`'s closest hit along o + t·d, t in [0, t_max), into `rh` (its instID[0] the copy's id).
bool enter_copy(const SweepCopy& c, const Vec3& o, const Vec3& d, float t_max, RTCRayHit& rh) {
  RTCRayHit h;  // Embree reads only the ray and the hit's ids
  set_object_ray(h.ray, c.frame, o, d, 0.0f, t_max);
  h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  h.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(c.prototype, &context, &h);
  if (h.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  rh = h;
  rh.hit.instID[0] = c.id;
  return true;
}

bool copy_occludes(const SweepCopy& c, const Vec3& o, const Vec3& d, float t_max) {
  RTCRay r;
  set_object_ray(r, c.frame, o, d, 0.0f, t_max);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(c.prototype, &context, &r);
  return r.tfar < 0.0f;
}

// Whether the ray leaves copy `from` from inside its box: a ray leaving a leaf inside its crown's
// box, worth tracing in that crown first; not one leaving a ground plane, whose flat box an origin
// lifted off the surface lies outside of, and which the ray cannot meet again.
bool leaves_from_inside(const InstanceSweep& s, size_t from, const Vec3& o) {
  return from < s.copies.size() && (s.boxes.valid() >> from & 1) && s.boxes.contains(from, o);
}

// The closest hit over the sweep's copies, in `rh` (its instID[0] the copy's instance id). `from`:
// the copy whose surface the ray leaves, if known (else ≥ the copy count). When the ray leaves it from
// inside its box, that copy is entered first, and if its hit ends the segment inside the box, only
// the copies whose boxes overlap it can hold a nearer hit: no other is tested. Any `from` gives the
// same hit (up to the order of exact ties): it only saves work.
bool sweep_intersect(const InstanceSweep& s, const Vec3& o, const Vec3& d, float t_max, size_t from, RTCRayHit& rh) {
  const InstanceBoxes& boxes = s.boxes;
  const Vec3 inv = InstanceBoxes::inverse_direction(d);
  float t_best = t_max;
  bool found = false;
  uint64_t left = boxes.valid();
  if (leaves_from_inside(s, from, o)) {
    left &= ~(uint64_t{1} << from);
    found = enter_copy(s.copies[from], o, d, t_best, rh);
    if (found) t_best = rh.ray.tfar;
    if (found && boxes.contains(from, o + t_best * d)) {
      for (uint64_t m = boxes.overlapping(from); m != 0; m &= m - 1) {
        const auto j = static_cast<size_t>(std::countr_zero(m));
        if (boxes.entry(j, o, inv, t_best) <= t_best && enter_copy(s.copies[j], o, d, t_best, rh)) t_best = rh.ray.tfar;
      }
      return true;
    }
  }
  alignas(32) float near[InstanceBoxes::kMaxCopies];
  left &= boxes.meet(o, inv, t_best, near);
  while (left != 0) {
    const size_t j = take_nearest(left, near);
    if (near[j] > t_best) break;  // every box left begins beyond the closest hit
    if (enter_copy(s.copies[j], o, d, t_best, rh)) {
      t_best = rh.ray.tfar;
      found = true;
    }
  }
  return found;
}

// Whether any of the sweep's copies blocks the segment: `from` (as for sweep_intersect) first, then
// the boxes the segment meets, nearest first.
bool sweep_occluded(const InstanceSweep& s, const Vec3& o, const Vec3& d, float t_max, size_t from) {
  uint64_t left = s.boxes.valid();
  if (leaves_from_inside(s, from, o)) {
    if (copy_occludes(s.copies[from], o, d, t_max)) return true;
    left &= ~(uint64_t{1} << from);
  }
  alignas(32) float near[InstanceBoxes::kMaxCopies];
  left &= s.boxes.meet(o, InstanceBoxes::inverse_direction(d), t_max, near);
  while (left != 0)
    if (copy_occludes(s.copies[take_nearest(left, near)], o, d, t_max)) return true;
  return false;
}

std::atomic<int64_t> g_embree_bytes{0};
std::atomic<int64_t> g_embree_peak{0};

bool memory_monitor(void*, ssize_t bytes, bool) {
  const int64_t now = g_embree_bytes.fetch_add(bytes) + bytes;
  int64_t peak = g_embree_peak.load();
  while (now > peak && !g_embree_peak.compare_exchange_weak(peak, now)) {
  }
  return true;
}

void check(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw Error(fmt::format("embree: {} failed (error {})", what, static_cast<int>(e)));
}

}  // namespace

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  std::vector<RTCScene> prototypes;
  std::vector<EmbreePrototype> geometry;  // per prototype: what its kinds left for decoding hits
  std::vector<uint32_t> instance_prototype;
  // Per prototype its object-space bounds (prototype_bounds: the union of its kinds' boxes); `array`
  // points into them, the prototypes' scenes and the Scene's instances (the instance array and the
  // sweep read it).
  std::vector<Bounds3> prototype_bounds;
  InstanceArray array;
  // A scene of few copies (uses_instance_sweep): traced by the sweep, not through `top` (left empty).
  InstanceSweep sweep;
  bool sweeping = false;
  // Cyclic plot: the cell [lo, hi] (x, y), its period, and the heights outside which no geometry lies.
  bool cyclic = false;
  Vec2 lo{0.0f}, hi{0.0f}, period{0.0f};
  float z_lo = 0, z_hi = 0;

  ~Impl() {
    if (top) rtcReleaseScene(top);
    for (RTCScene s : prototypes)
      if (s) rtcReleaseScene(s);
    if (device) rtcReleaseDevice(device);
  }
};

EmbreeScene::EmbreeScene(const Scene& scene) : EmbreeScene(scene, TransportFaults{}, BvhBuild::kThorough) {}

EmbreeScene::EmbreeScene(const Scene& scene, const TransportFaults& faults)
    : EmbreeScene(scene, faults, BvhBuild::kThorough) {}

EmbreeScene::EmbreeScene(const Scene& scene, BvhBuild build, EmbreeIsa isa)
    : EmbreeScene(scene, TransportFaults{}, build, isa) {}

EmbreeScene::EmbreeScene(const Scene& scene, const TransportFaults& faults, BvhBuild build, EmbreeIsa isa)
    : scene_(&scene), impl_(std::make_unique<Impl>()) {
  const auto start = std::chrono::steady_clock::now();
  g_embree_peak = g_embree_bytes.load();
  const int64_t base_bytes = g_embree_bytes.load();
  // Embree takes the processor's widest kernels unless capped (EmbreeIsa: Sylva caps them at AVX2
  // unless asked, so that a render's bits reproduce on every machine with AVX2).
  const std::string config =
      isa == EmbreeIsa::kNative ? "verbose=0" : fmt::format("verbose=0,max_isa={}", embree_isa_name(isa));
  impl_->device = rtcNewDevice(config.c_str());
  if (!impl_->device) throw Error("embree: cannot create device");
  stats_.isa = resolve_embree_isa(isa);
  rtcSetDeviceErrorFunction(impl_->device, error_callback, nullptr);
  rtcSetDeviceMemoryMonitorFunction(impl_->device, memory_monitor, nullptr);
  RTCDevice device = impl_->device;

  const std::vector<bool> robust = robust_prototypes(scene);
  impl_->geometry.resize(scene.prototypes.size());
  for (size_t p = 0; p < scene.prototypes.size(); ++p) {
    const Prototype& proto = scene.prototypes[p];
    validate_prototype(proto);
    RTCScene s = rtcNewScene(device);
    if (robust[p]) rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(s, build == BvhBuild::kThorough ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    EmbreePrototype& e = impl_->geometry[p];
    e.device = device;
    e.scene = s;
    e.robust = robust[p];
    e.no_shadow_alpha = faults.no_shadow_alpha;
    e.stats = &stats_;
    attach_prototype(e, proto);
    impl_->prototype_bounds.push_back(prototype_bounds(proto));
    rtcCommitScene(s);
    check(device, "building a prototype BVH");
    impl_->prototypes.push_back(s);
  }

  impl_->top = rtcNewScene(device);
  rtcSetSceneFlags(impl_->top,
                   RTC_SCENE_FLAG_ROBUST | (uses_instance_array(scene) ? RTC_SCENE_FLAG_COMPACT : RTC_SCENE_FLAG_NONE));
  rtcSetSceneBuildQuality(impl_->top, RTC_BUILD_QUALITY_HIGH);
  const PlotDesc& plot = scene.plot;
  impl_->cyclic = plot.defined && plot.cyclic;
  if (impl_->cyclic) {
    if (!(plot.hi.x > plot.lo.x && plot.hi.y > plot.lo.y)) throw Error("a cyclic plot needs a non-empty rectangle");
    impl_->lo = plot.lo;
    impl_->hi = plot.hi;
    impl_->period = plot.hi - plot.lo;
  }
  const int copies = impl_->cyclic ? 9 : 1;
  const size_t n_instances = scene.instances.size();
  impl_->instance_prototype.reserve(n_instances);
  for (size_t i = 0; i < n_instances; ++i) {
    const Instance& inst = scene.instances[i];
    if (inst.prototype >= impl_->prototypes.size())
      throw Error(fmt::format("instance {} refers to missing prototype {}", i, inst.prototype));
    impl_->instance_prototype.push_back(inst.prototype);
    const Prototype& p = scene.prototypes[inst.prototype];
    stats_.instanced_triangles += p.triangles.triangles.size();
    stats_.instanced_leaf_quads += p.leaves.size();
    stats_.instanced_curves += p.curves.size();
  }
  impl_->array = InstanceArray{scene.instances.data(), impl_->prototypes.data(), impl_->prototype_bounds.data(),
                               static_cast<uint32_t>(n_instances), impl_->period};
  // The scene's bounds: every instance's box of its prototype's kinds (one period of a cyclic plot),
  // the boxes the label sidecar reports and the instance array and the sweep cull by.
  for (uint32_t i = 0; i < n_instances; ++i) {
    const Bounds3 b = array_instance_bounds(impl_->array, i, 0);
    if (!b.empty()) {
      bounds_.extend(b.lo);
      bounds_.extend(b.hi);
    }
  }
  stats_.instance_array = uses_instance_array(scene);
  stats_.instance_sweep = !stats_.instance_array && uses_instance_sweep(scene) && n_instances > 0;
  if (stats_.instance_array)
    add_instance_array(scene, copies);
  else if (stats_.instance_sweep)
    add_sweep(scene, copies);
  else
    add_native_instances(scene, copies);
  stats_.instances = n_instances;
  rtcCommitScene(impl_->top);
  check(device, "building the instance BVH");
  impl_->z_lo = bounds_.lo.z;
  impl_->z_hi = bounds_.hi.z;
  stats_.bvh_bytes = static_cast<size_t>(std::max<int64_t>(0, g_embree_peak.load() - base_bytes));
  stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

EmbreeScene::~EmbreeScene() = default;

// One Embree instance per copy: copy k of instance i has the Embree id k·N + i (copy 0 is the
// instance itself, copies 1–8 its shifts by whole periods in a cyclic plot).
void EmbreeScene::add_native_instances(const Scene& scene, int copies) {
  const size_t n_instances = scene.instances.size();
  for (int k = 0; k < copies; ++k) {
    for (size_t i = 0; i < n_instances; ++i) {
      const Instance& inst = scene.instances[i];
      RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(g, impl_->prototypes[inst.prototype]);
      const Vec2 offset = kCellShifts[k] * impl_->period;
      float xfm[12];
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 3; ++r) xfm[3 * c + r] = inst.world_from_object[c][r];
      xfm[9] += offset.x;
      xfm[10] += offset.y;
      rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
      rtcCommitGeometry(g);
      const unsigned id = rtcAttachGeometry(impl_->top, g);
      rtcReleaseGeometry(g);
      if (id != k * n_instances + i) throw Error("embree: unexpected instance id");
    }
  }
}

// The sweep over the scene's copies (copy k of instance i at index k·N + i, as the native ids).
void EmbreeScene::add_sweep(const Scene& scene, int copies) {
  Impl& m = *impl_;
  const size_t n = scene.instances.size(), total = n * static_cast<size_t>(copies);
  std::vector<Bounds3> boxes;
  for (size_t j = 0; j < total; ++j) {
    const auto i = static_cast<uint32_t>(j % n), k = static_cast<uint32_t>(j / n);
    const Instance& inst = scene.instances[i];
    m.sweep.copies.push_back(
        SweepCopy{copy_frame(inst, k, m.period), m.prototypes[inst.prototype], static_cast<unsigned>(j)});
    boxes.push_back(array_instance_bounds(m.array, i, k));
  }
  m.sweep.boxes = InstanceBoxes(boxes);
  m.sweeping = true;
}

// The instance array: one user geometry of copies·N primitives (primitive k·N + i is copy k of
// instance i, as the native ids); nothing stored per instance beyond the Scene's.
void EmbreeScene::add_instance_array(const Scene& scene, int copies) {
  const size_t n_instances = scene.instances.size();
  if (n_instances == 0) return;
  if (n_instances * static_cast<size_t>(copies) >= RTC_INVALID_GEOMETRY_ID)
    throw Error(fmt::format("{} instances are more than the instance array holds", n_instances));
  Impl& m = *impl_;
  RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(n_instances * static_cast<size_t>(copies)));
  rtcSetGeometryUserData(g, &m.array);
  rtcSetGeometryBoundsFunction(g, array_bounds, nullptr);
  rtcSetGeometryIntersectFunction(g, array_intersect);
  rtcSetGeometryOccludedFunction(g, array_occluded);
  rtcCommitGeometry(g);
  rtcAttachGeometry(m.top, g);
  rtcReleaseGeometry(g);
}

bool EmbreeScene::intersect(const Ray& ray, RayHit* hit, uint32_t from) const {
  if (!impl_->cyclic) return intersect_cell(ray, hit, from);
  const Impl& m = *impl_;
  const Vec3& d = ray.direction;
  CellWalk walk;
  if (!start_walk(m.z_lo, m.z_hi, m.lo, m.period, ray.origin, d, walk)) return false;
  int crossings = 0;
  while (walk.travelled < ray.t_max) {
    next_segment(walk, d, m.lo, m.hi);
    const float remaining = ray.t_max - walk.travelled;
    if (intersect_cell(Ray{walk.origin, d, std::min(walk.segment, remaining)}, hit, kNoInstance)) {
      hit->t += walk.travelled;
      return true;
    }
    if (walk.segment >= remaining || !cross_wall(walk, d, m.lo, m.hi, m.z_lo, m.z_hi, crossings)) return false;
  }
  return false;
}

bool EmbreeScene::occluded(const Vec3& origin, const Vec3& direction, float t_max, uint32_t from) const {
  if (!impl_->cyclic) return occluded_cell(origin, direction, t_max, from);
  const Impl& m = *impl_;
  const Vec3& d = direction;
  CellWalk walk;
  if (!start_walk(m.z_lo, m.z_hi, m.lo, m.period, origin, d, walk)) return false;
  int crossings = 0;
  while (walk.travelled < t_max) {
    next_segment(walk, d, m.lo, m.hi);
    const float remaining = t_max - walk.travelled;
    if (occluded_cell(walk.origin, d, std::min(walk.segment, remaining), kNoInstance)) return true;
    if (walk.segment >= remaining || !cross_wall(walk, d, m.lo, m.hi, m.z_lo, m.z_hi, crossings)) return false;
  }
  return false;
}

bool EmbreeScene::intersect_cell(const Ray& ray, RayHit* hit, uint32_t from) const {
  RTCRayHit rh;  // Embree reads only the ray and the hit's ids
  if (impl_->sweeping) {
    if (!sweep_intersect(impl_->sweep, ray.origin, ray.direction, ray.t_max, from, rh)) return false;
  } else {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    set_rtc_ray(rh.ray, ray.origin, ray.direction, 0.0f, ray.t_max);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->top, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  }
  hit->t = rh.ray.tfar;
  hit->instance = rh.hit.instID[0];
  if (impl_->cyclic && hit->instance != RTC_INVALID_GEOMETRY_ID)
    hit->instance %= static_cast<uint32_t>(impl_->instance_prototype.size());
  hit->primitive = rh.hit.primID;
  hit->u = rh.hit.u;
  hit->v = rh.hit.v;
  if (hit->instance == RTC_INVALID_GEOMETRY_ID) return false;
  const EmbreePrototype& e = impl_->geometry[impl_->instance_prototype[hit->instance]];
  hit->kind = e.kind_of[rh.hit.geomID];
  switch (hit->kind) {
    case PrimitiveKind::kTriangles:
      decode_embree_triangle_hit(e, rh.hit.primID, rh.hit.u, rh.hit.v, hit);
      break;
    case PrimitiveKind::kCurves:
      decode_embree_curve_hit(e, rh.hit.primID, Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), hit);
      break;
    case PrimitiveKind::kSolids:
      hit->normal = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
      break;
    case PrimitiveKind::kLeafQuads:
    case PrimitiveKind::kDiscs:
      break;
  }
  return true;
}

bool EmbreeScene::occluded_cell(const Vec3& origin, const Vec3& direction, float t_max, uint32_t from) const {
  if (impl_->sweeping) return sweep_occluded(impl_->sweep, origin, direction, t_max, from);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  set_rtc_ray(ray, origin, direction, 0.0f, t_max);
  rtcOccluded1(impl_->top, &context, &ray);
  return ray.tfar < 0.0f;
}

}  // namespace sylva
