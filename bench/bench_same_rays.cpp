// Sylva's ray tracing against a plain Embree BVH on the very same rays (issue 11; bench/README.md
// "Same rays").
//
// bench/compare_embree.sh compares Sylva with Embree's pathtracer tutorial on one scene, but the
// two renderers trace different rays: the tutorial's opaque leaves trap its paths in short bounces
// inside the crowns (17 rays a path in the forest), Sylva's translucent leaves let paths leave the
// crown in long rays (6 a path), and a ray's cost depends on how far it travels through the
// forest. Rays per second then compares different rays. This benchmark takes the difference out:
// one ray set, traced by both.
//
// The reference is what the tutorial builds from `sylva export`'s OBJ: the scene flattened
// (render/flatten.h) into one triangle geometry in one BVH, Embree's default scene flags (no robust
// mode), medium build quality, no filters (leaves are opaque full quads). The rays are a path
// tracer's, made in the reference: one path per pixel of a 320×180 view, each vertex adding a
// shadow ray towards the sun and a cosine-distributed bounce about the geometric normal, up to 8
// bounces — the tutorial's kind of rays. Sylva traces each through EmbreeScene::intersect (closest
// hit, decoded to instance, primitive and leaf coordinates) or EmbreeScene::occluded: instanced
// prototypes, leaf alpha outlines, robust mode on large prototypes. The rays that pass a leaf's
// cut-out in Sylva travel further than in the reference: that is Sylva's real work on those rays.
//
// Embree is called directly here, outside render/embree_scene.cpp, because the reference is
// Embree itself.

#include "core/rng.h"
#include "core/sampling.h"
#include "render/embree_scene.h"
#include "render/flatten.h"
#include "render/lights/lights.h"
#include "render/sensors/camera.h"
#include "scenes/scene_file.h"

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace sylva {
namespace {

struct TracedRay {
  Vec3 origin;
  Vec3 direction;
  float t_max = std::numeric_limits<float>::infinity();
};

// The reference BVH and the rays made in it.
struct SameRays {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<TracedRay> closest, shadow;
  size_t triangles = 0;

  ~SameRays() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  bool hit(const TracedRay& r, RTCRayHit& rh) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rh = RTCRayHit{};
    rh.ray.org_x = r.origin.x;
    rh.ray.org_y = r.origin.y;
    rh.ray.org_z = r.origin.z;
    rh.ray.dir_x = r.direction.x;
    rh.ray.dir_y = r.direction.y;
    rh.ray.dir_z = r.direction.z;
    rh.ray.tfar = r.t_max;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }

  bool occluded(const TracedRay& r) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    ray.org_x = r.origin.x;
    ray.org_y = r.origin.y;
    ray.org_z = r.origin.z;
    ray.dir_x = r.direction.x;
    ray.dir_y = r.direction.y;
    ray.dir_z = r.direction.z;
    ray.tfar = r.t_max;
    ray.mask = 0xffffffffu;
    rtcOccluded1(scene, &context, &ray);
    return ray.tfar < 0.0f;
  }
};

constexpr int kWidth = 320, kHeight = 180, kMaxBounces = 8;

std::unique_ptr<SameRays> make_same_rays(const SceneFile& file) {
  auto out = std::make_unique<SameRays>();
  const TriangleMesh world = flatten_scene(file.scene).mesh;
  out->triangles = world.triangles.size();
  out->device = rtcNewDevice("verbose=0,max_isa=avx2");
  out->scene = rtcNewScene(out->device);
  rtcSetSceneBuildQuality(out->scene, RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry g = rtcNewGeometry(out->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), world.positions.size()));
  for (size_t i = 0; i < world.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = world.positions[i][k];
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), world.triangles.size()));
  for (size_t i = 0; i < world.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) idx[3 * i + k] = world.triangles[i][k];
  rtcCommitGeometry(g);
  rtcAttachGeometry(out->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(out->scene);

  const Camera camera(file.scene.camera, kWidth, kHeight);
  const Vec3 to_sun = sun_direction(file.scene.sun.azimuth_deg, file.scene.sun.elevation_deg);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      Pcg32 rng(hash_ids(1, static_cast<uint64_t>(x), static_cast<uint64_t>(y)));
      const Ray primary =
          camera.generate_ray(Vec2(static_cast<float>(x), static_cast<float>(y)) + uniform2(rng), uniform2(rng));
      TracedRay ray{primary.origin, primary.direction, primary.t_max};
      for (int bounce = 0; bounce <= kMaxBounces; ++bounce) {
        out->closest.push_back(ray);
        RTCRayHit rh;
        if (!out->hit(ray, rh)) break;
        Vec3 n = glm::normalize(Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
        if (glm::dot(n, ray.direction) > 0.0f) n = -n;
        const Vec3 p = ray.origin + rh.ray.tfar * ray.direction + 1e-4f * n;
        if (glm::dot(n, to_sun) > 0.0f) out->shadow.push_back({p, to_sun});
        ray = {p, Frame::from_z(n).to_world(sample_cosine_hemisphere(uniform2(rng)))};
      }
    }
  return out;
}

const SceneFile& forest() {
  static const SceneFile file = load_scene_file(SYLVA_BENCH_SCENES_DIR "/forest_no_grass.toml");
  return file;
}
const SameRays& same_rays() {
  static const std::unique_ptr<SameRays> rays = make_same_rays(forest());
  return *rays;
}
const EmbreeScene& sylva_scene() {
  static const EmbreeScene embree(forest().scene, BvhBuild::kFast);
  return embree;
}

enum class Tracer { kReference, kSylva };

// One iteration = every closest-hit ray of the set (or every shadow ray), one thread.
void bm_same_rays(benchmark::State& state, Tracer tracer, bool shadow) {
  const SameRays& set = same_rays();
  const EmbreeScene& embree = sylva_scene();
  const std::vector<TracedRay>& rays = shadow ? set.shadow : set.closest;
  uint64_t traced = 0, hits = 0;
  for (auto _ : state) {
    for (const TracedRay& r : rays) {
      bool hit;
      if (shadow) {
        hit = tracer == Tracer::kReference ? set.occluded(r) : embree.occluded(r.origin, r.direction, r.t_max);
      } else if (tracer == Tracer::kReference) {
        RTCRayHit rh;
        hit = set.hit(r, rh);
      } else {
        RayHit h;
        hit = embree.intersect(Ray{r.origin, r.direction, r.t_max}, &h);
      }
      hits += hit;
    }
    traced += rays.size();
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(traced), benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = static_cast<double>(hits) / static_cast<double>(std::max<uint64_t>(traced, 1));
  state.counters["rays"] = static_cast<double>(rays.size());
  state.counters["reference_triangles"] = static_cast<double>(set.triangles);
}

}  // namespace

BENCHMARK_CAPTURE(bm_same_rays, reference_closest, Tracer::kReference, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_same_rays, sylva_closest, Tracer::kSylva, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_same_rays, reference_shadow, Tracer::kReference, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_same_rays, sylva_shadow, Tracer::kSylva, true)->Unit(benchmark::kMillisecond);

}  // namespace sylva
