// Half-space solids through Embree (render/embree_scene.cpp user geometry): instanced closest hits
// and occlusion agree with intersect_solid in object space, for exact and displaced crowns.

#include "core/band.h"
#include "core/error.h"
#include "core/rng.h"
#include "geometry/primitives.h"
#include "geometry/trees/fournier_grindal/fournier_grindal.h"
#include "render/embree_scene.h"
#include "render/integrator.h"
#include "render/materials/diffuse.h"
#include "render/materials/leaf.h"
#include "render/materials/leaf_medium.h"

#include <glm/gtc/matrix_transform.hpp>

#include <bit>

#include <gtest/gtest.h>

namespace sylva {
namespace {

TEST(EmbreeSolids, InstancedHitsMatchDirectIntersection) {
  for (const float displacement : {0.0f, 0.3f}) {
    FournierGrindalParams fg;
    fg.normals = {{2, 0, 0}, {-2, 0, 0}, {0, 2, 0}, {0, -2, 0}, {0, 0, 3}, {0, 0, -1.5f}};
    fg.displacement_m = displacement;
    Scene scene;
    Prototype p;
    p.solids = make_fournier_grindal_tree(fg, 9).solids;
    p.solid_palettes.assign(p.solids.size(), {0u});
    scene.add_prototype(p);
    const Mat4 xf = glm::scale(glm::rotate(glm::translate(Mat4(1.0f), Vec3(3, -1, 0)), 0.7f, Vec3(0, 0, 1)),
                               Vec3(1.5f, 1.5f, 2.0f));
    scene.instances.push_back({0, xf, 0});
    const EmbreeScene embree(scene);
    EXPECT_EQ(embree.stats().solids, 2u);
    const Mat4 inv = glm::inverse(xf);
    Pcg32 rng(5);
    int hits = 0;
    for (int i = 0; i < 400; ++i) {
      const Vec3 o = Vec3(3, -1, 4) + 25.0f * glm::normalize(Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric()));
      const Vec3 target = Vec3(3, -1, 5) + Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric()) * 5.0f;
      const Vec3 d = glm::normalize(target - o);
      // The reference: the nearest solid hit in object space (same t, affine map).
      const Vec3 oo = Vec3(inv * Vec4(o, 1.0f)), od = Vec3(inv * Vec4(d, 0.0f));
      float best = std::numeric_limits<float>::infinity();
      uint32_t best_prim = 0;
      Vec3 best_normal(0.0f);
      for (size_t k = 0; k < p.solids.size(); ++k) {
        SolidHit h;
        if (intersect_solid(p.solids[k], oo, od, 0.0f, best, &h)) {
          best = h.t;
          best_prim = static_cast<uint32_t>(k);
          best_normal = h.normal;
        }
      }
      RayHit hit;
      const bool found = embree.intersect(Ray{o, d}, &hit);
      ASSERT_EQ(found, std::isfinite(best)) << "ray " << i;
      EXPECT_EQ(embree.occluded(o, d, std::numeric_limits<float>::infinity()), found);
      if (!found) continue;
      ++hits;
      EXPECT_EQ(hit.kind, PrimitiveKind::kSolids);
      EXPECT_EQ(hit.instance, 0u);
      EXPECT_EQ(hit.primitive, best_prim);
      EXPECT_NEAR(hit.t, best, 1e-3f * best);
      EXPECT_GT(glm::dot(hit.normal, best_normal), 0.999f);
      // Occlusion stops short of the hit: nothing in front.
      EXPECT_FALSE(embree.occluded(o, d, 0.99f * hit.t));
    }
    EXPECT_GT(hits, 100);
  }
}

// A cube [-1, 1]³ (scaled by the instance) as a turbid crown.
HalfSpaceSolid turbid_cube(float lad) {
  HalfSpaceSolid s;
  for (int axis = 0; axis < 3; ++axis)
    for (const float sign : {-1.0f, 1.0f}) {
      Vec3 n(0.0f);
      n[axis] = sign;
      s.planes.push_back(HalfSpace{n, 1.0f});
    }
  s.leaf_area_density = lad;
  finish_solid(s);
  return s;
}

// A scene of turbid cubes: per (LAD, world_from_object), a prototype holding one and its copy.
Scene turbid_cubes(const std::vector<std::pair<float, Mat4>>& cubes) {
  Scene scene;
  for (const auto& [lad, world_from_object] : cubes) {
    Prototype p;
    p.solids = {turbid_cube(lad)};
    p.solid_palettes = {{0u}};
    scene.instances.push_back({scene.add_prototype(p), world_from_object, 0});
  }
  return scene;
}

TEST(TurbidCrown, TransmittanceIsBeersLaw) {
  // Two turbid cubes (LAD 1.5 and 0.6, the second scaled ×2) and an opaque one: along any segment
  // missing the opaque cube, T = exp(−G·Σ LAD_i·path_i) with G = 1/2; shadow rays ignore media.
  const Scene scene =
      turbid_cubes({{1.5f, Mat4(1.0f)}, {0.6f, glm::scale(glm::translate(Mat4(1.0f), Vec3(6, 0, 0)), Vec3(2.0f))}});
  const HalfSpaceSolid& a = scene.prototypes[0].solids[0];
  const HalfSpaceSolid& b = scene.prototypes[1].solids[0];
  const EmbreeScene embree(scene);
  const Environment environment;
  const Integrator integrator(scene, embree, environment, IntegratorSettings{});
  Pcg32 rng(8);
  uint64_t rays = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 o(-5.0f, rng.symmetric() * 0.9f, rng.symmetric() * 0.9f);
    const Vec3 target(12.0f, rng.symmetric() * 0.9f, rng.symmetric() * 0.9f);
    const Vec3 d = glm::normalize(target - o);
    // Path lengths inside each box by clipping (the reference, independent of Embree).
    double optical = 0.0;
    for (const auto& [solid, inst] : {std::pair{&a, 0}, std::pair{&b, 1}}) {
      const Mat4 inv = glm::inverse(scene.instances[size_t(inst)].world_from_object);
      const RaySpan span = clip_ray(solid->planes, Vec3(inv * Vec4(o, 1.0f)), Vec3(inv * Vec4(d, 0.0f)));
      if (!span.empty() && span.t_exit > 0)
        optical += kSphericalG * solid->leaf_area_density * (span.t_exit - std::max(0.0, span.t_entry));
    }
    ASSERT_GT(optical, 0.5);
    EXPECT_FALSE(embree.occluded(o, d, 100.0f));
    EXPECT_NEAR(integrator.medium_transmittance(o, d, rays), std::exp(-optical), 2e-4 * std::exp(-optical) + 1e-6);
    // From inside the first cube.
    const Vec3 inside(0.2f, 0.1f, -0.3f);
    const Vec3 d2 = glm::normalize(target - inside);
    const RaySpan s2 = clip_ray(a.planes, inside, d2);
    double optical2 = kSphericalG * 1.5 * s2.t_exit;
    const Mat4 inv = glm::inverse(scene.instances[1].world_from_object);
    const RaySpan s3 = clip_ray(b.planes, Vec3(inv * Vec4(inside, 1.0f)), Vec3(inv * Vec4(d2, 0.0f)));
    if (!s3.empty() && s3.t_exit > 0) optical2 += kSphericalG * 0.6 * (s3.t_exit - std::max(0.0, s3.t_entry));
    EXPECT_NEAR(integrator.medium_transmittance(inside, d2, rays), std::exp(-optical2), 2e-4);
  }
}

}  // namespace
TEST(TurbidCrown, TransmittanceThroughASmallScaledCrown) {
  // A turbid cube scaled to 2 cm (LAD 100): the normal matrix gives its world normals 100 times too
  // long, and a crossing's origin offset must not grow with them — offset 100 times too far, the ray
  // jumps centimetres, past the whole crown, which then lets everything through (T = 1 instead of
  // about e^−1).
  const Scene scene = turbid_cubes({{100.0f, glm::scale(glm::translate(Mat4(1.0f), Vec3(10, 0, 0)), Vec3(0.01f))}});
  const EmbreeScene embree(scene);
  const Environment environment;
  const Integrator integrator(scene, embree, environment, IntegratorSettings{});
  Pcg32 rng(9);
  uint64_t rays = 0;
  const Mat4 inv = glm::inverse(scene.instances[0].world_from_object);
  for (int i = 0; i < 100; ++i) {
    const Vec3 o(-5.0f, rng.symmetric() * 0.008f, rng.symmetric() * 0.008f);
    const Vec3 target(20.0f, rng.symmetric() * 0.008f, rng.symmetric() * 0.008f);
    const Vec3 d = glm::normalize(target - o);
    // Clipped in object space with the direction moved there unnormalised: t stays the world distance.
    const RaySpan span =
        clip_ray(scene.prototypes[0].solids[0].planes, Vec3(inv * Vec4(o, 1.0f)), Vec3(inv * Vec4(d, 0.0f)));
    ASSERT_FALSE(span.empty());
    const double optical = kSphericalG * 100.0 * (span.t_exit - std::max(0.0, span.t_entry));
    ASSERT_GT(optical, 0.5);
    // Each entry's offset (256 ulps of |p| ≈ 0.24 mm at 10 m, offset_ray_origin) is not counted as
    // inside: 1.2 % of this crown's optical depth.
    EXPECT_NEAR(integrator.medium_transmittance(o, d, rays), std::exp(-optical), 0.03 * std::exp(-optical));
  }
}

}  // namespace sylva

namespace sylva {
namespace {

// Every path of `origins` (towards the scene's centre, one per origin) by radiance(), and the same
// paths eight at a time through Integrator::trace_paths, as Renderer::render_pixel runs them: each
// path's radiance, random numbers and ray count must be the same.
void expect_batched_paths_match(const Scene& scene, const std::vector<Vec3>& origins) {
  SunDesc sun;
  sun.elevation_deg = 35;
  SkyDesc sky;
  const Environment environment(sun, sky);
  const EmbreeScene embree(scene);
  const Integrator integrator(scene, embree, environment, IntegratorSettings{});
  const WavelengthSampler sampler({resolve_band("rgb"), resolve_band("nir")});
  constexpr int kBatch = 8;
  int nonzero = 0;
  for (size_t start = 0; start < origins.size(); start += kBatch) {
    const int n = static_cast<int>(std::min<size_t>(kBatch, origins.size() - start));
    std::vector<Pcg32> rngs;
    std::vector<Ray> rays_in;
    std::vector<SampledWavelengths> wls;
    for (int k = 0; k < n; ++k) {
      rngs.emplace_back(1000 + start + static_cast<size_t>(k));
      wls.push_back(sampler.sample(rngs.back().uniform(), rngs.back().uniform()));
      const Vec3 target(rngs.back().symmetric() * 3.0f, rngs.back().symmetric() * 3.0f, 0.5f);
      rays_in.push_back(Ray{origins[start + static_cast<size_t>(k)],
                            glm::normalize(target - origins[start + static_cast<size_t>(k)])});
    }
    std::vector<Pcg32> alone_rngs = rngs;
    std::vector<FirstHit> firsts(static_cast<size_t>(n)), alone_firsts(static_cast<size_t>(n));
    std::vector<PathSampler> samplers(rngs.begin(), rngs.end());  // independent draws from rngs
    std::vector<PathState> paths;
    for (int k = 0; k < n; ++k)
      paths.emplace_back(rays_in[size_t(k)], wls[size_t(k)], samplers[size_t(k)], &firsts[size_t(k)]);
    uint64_t batched_rays = 0;
    integrator.trace_paths(paths, batched_rays);
    uint64_t alone_rays = 0;
    for (int k = 0; k < n; ++k) {
      const SampledSpectrum alone = integrator.radiance(rays_in[size_t(k)], wls[size_t(k)], alone_rngs[size_t(k)],
                                                        &alone_firsts[size_t(k)], alone_rays);
      for (int i = 0; i < kLambdaCount; ++i) {
        EXPECT_EQ(std::bit_cast<uint32_t>(alone[i]), std::bit_cast<uint32_t>(paths[size_t(k)].L[i]))
            << "path " << start + size_t(k) << " wavelength " << i;
        EXPECT_EQ(std::bit_cast<uint32_t>(alone_firsts[size_t(k)].albedo[i]),
                  std::bit_cast<uint32_t>(firsts[size_t(k)].albedo[i]));
      }
      nonzero += max_component(alone) > 0 ? 1 : 0;
      EXPECT_EQ(alone_rngs[size_t(k)].next_u32(), rngs[size_t(k)].next_u32()) << "the same random numbers, in order";
    }
    EXPECT_EQ(alone_rays, batched_rays);
  }
  EXPECT_GT(nonzero, static_cast<int>(origins.size()) / 2) << "the paths must gather light";
  // More paths than the batch holds: an error, not an overflow.
  Pcg32 rng(5);
  PathSampler path_sampler(rng);
  std::vector<PathState> too_many(
      Integrator::kMaxPaths + 1,
      PathState(Ray{origins[0], Vec3(0, 0, -1)}, sampler.sample(0.5f, 0.5f), path_sampler, nullptr));
  uint64_t rays = 0;
  EXPECT_THROW(integrator.trace_paths(too_many, rays), Error);
}

TEST(PathState, BatchedBouncesGiveRadianceBits) {
  // Turbid crowns over a leaf-white floor, with and without haze: surface, crown and haze shadow
  // rays (every ShadowQuery kind), crown crossings, escapes and roulette.
  Scene scene =
      turbid_cubes({{1.5f, Mat4(1.0f)}, {0.6f, glm::scale(glm::translate(Mat4(1.0f), Vec3(4, 0, 0)), Vec3(2.0f))}});
  scene.add_material("leaf", make_leaf("leaf", DenseSpectrum::constant(0.45f), DenseSpectrum::constant(0.5f)));
  Prototype floor;
  floor.triangles = make_plane(40.0f, 40.0f);
  floor.triangle_material = scene.add_material("white", make_diffuse("white", DenseSpectrum::constant(0.8f)));
  scene.instances.push_back({scene.add_prototype(floor), glm::translate(Mat4(1.0f), Vec3(0, 0, -2)), 0});
  Pcg32 rng(77);
  std::vector<Vec3> origins;
  for (int i = 0; i < 60; ++i)
    origins.emplace_back(rng.symmetric() * 8.0f, rng.symmetric() * 8.0f, 6.0f + 4.0f * rng.uniform());
  expect_batched_paths_match(scene, origins);
  scene.haze.enabled = true;
  scene.haze.extinction_550 = 0.08f;
  scene.haze.top = 12.0f;
  expect_batched_paths_match(scene, origins);
}

}  // namespace
}  // namespace sylva
