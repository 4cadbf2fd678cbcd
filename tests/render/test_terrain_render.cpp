// Terrain and grass in the Embree backend: no self-intersection on a kilometre-scale terrain far from
// the origin (ray origins offset in ulps of the coordinates, render/integrator.h), and grass blades
// hit as two-sided curves that a leaving ray never re-hits.

#include "core/rng.h"
#include "geometry/grass.h"
#include "geometry/terrain.h"
#include "render/embree_scene.h"
#include "render/integrator.h"
#include "render/materials/material.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

TEST(TerrainRender, NoSelfIntersectionOnAKilometreScaleTerrainFarFromTheOrigin) {
  // A tilted plane meshed as a 2 km terrain of 10 m cells, 5 km from the origin: every shadow ray
  // leaving its upper side is unoccluded, so any occlusion is acne.
  HeightField f;
  f.width = f.height = 201;
  f.min_m = Vec2(4000.0f, 4000.0f);
  f.spacing_m = Vec2(10.0f);
  for (int j = 0; j < f.height; ++j)
    for (int i = 0; i < f.width; ++i)
      f.heights.push_back(300.0f + 0.05f * 10.0f * static_cast<float>(i) + 0.02f * 10.0f * static_cast<float>(j));
  Scene s;
  const uint32_t m = s.add_material("soil", make_diffuse("soil", DenseSpectrum::constant(0.3f)));
  Prototype p;
  p.name = "terrain";
  p.triangles = make_terrain_mesh(f);
  p.triangle_material = m;
  s.instances.push_back({s.add_prototype(std::move(p)), Mat4(1.0f), 0});
  const EmbreeScene embree(s);
  const Vec3 n = glm::normalize(Vec3(-0.05f, -0.02f, 1.0f));
  Pcg32 rng(1);
  int hits = 0, acne_shadow = 0, acne_bounce = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vec3 o(rng.uniform(4100.0f, 5900.0f), rng.uniform(4100.0f, 5900.0f), 2000.0f);
    const Vec3 d = glm::normalize(Vec3(rng.uniform(-0.05f, 0.05f), rng.uniform(-0.05f, 0.05f), -1.0f));
    RayHit hit;
    if (!embree.intersect(Ray{o, d}, &hit)) continue;
    ++hits;
    const Vec3 q = offset_ray_origin(o + hit.t * d, n);
    // A direction in the upper half-space of the plane, down to grazing (cos = 0.001).
    Vec3 w;
    do {
      w = glm::normalize(Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric()));
    } while (glm::dot(w, n) < 0.001f);
    acne_shadow += embree.occluded(q, w, std::numeric_limits<float>::infinity());
    RayHit again;
    acne_bounce += embree.intersect(Ray{q, w}, &again);
  }
  EXPECT_GT(hits, 3900);
  EXPECT_EQ(acne_shadow, 0);
  EXPECT_EQ(acne_bounce, 0);
}

// A 1 m patch of dense grass, traced as triangle strips or (exact) as Embree's curves.
Scene grass_patch_scene(bool exact) {
  GrassParams g;
  g.patch_size_m = 1.0f;
  g.density_per_m2 = 3000.0f;
  g.width_m = 0.01f;
  Scene s;
  const uint32_t m =
      s.add_material("grass", make_leaf("grass", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.3f)));
  Prototype p;
  p.name = "grass";
  p.curves = make_grass_patch(g, 1);
  p.curves.exact = exact;
  p.curve_material = m;
  s.instances.push_back({s.add_prototype(std::move(p)), Mat4(1.0f), 0});
  return s;
}

class GrassTrace : public ::testing::TestWithParam<bool> {};

TEST_P(GrassTrace, GrassBladesAreTwoSidedAndNeverReHitWhenLeaving) {
  const Scene s = grass_patch_scene(GetParam());
  const EmbreeScene embree(s);
  EXPECT_EQ(embree.stats().curves, 3000u);
  Pcg32 rng(2);
  int hits = 0, rehits = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vec3 o(rng.uniform(-0.4f, 0.4f), -3.0f, rng.uniform(0.02f, 0.15f));
    const Vec3 d(0.0f, 1.0f, 0.0f);
    RayHit hit;
    if (!embree.intersect(Ray{o, d}, &hit)) continue;
    ++hits;
    ASSERT_EQ(hit.kind, PrimitiveKind::kCurves);
    ASSERT_LT(hit.primitive, 3000u);
    const Vec3 ng = glm::normalize(hit.normal);
    ASSERT_TRUE(is_finite(ng));
    // Transmitted straight through or reflected back: the ray leaving the blade must not hit the
    // same blade again at once.
    const Vec3 side = glm::dot(ng, d) < 0 ? ng : -ng;
    for (const Vec3& w : {d, -d}) {
      const Vec3 q = offset_ray_origin(o + hit.t * d, glm::dot(w, side) > 0 ? side : -side);
      RayHit next;
      if (embree.intersect(Ray{q, w}, &next) && next.primitive == hit.primitive && next.t < 1e-3f) ++rehits;
    }
  }
  EXPECT_GT(hits, 1000);  // a dense meadow seen edge-on from 3 m
  EXPECT_EQ(rehits, 0);
}

INSTANTIATE_TEST_SUITE_P(StripsAndCurves, GrassTrace, ::testing::Bool());

// The triangle strips the renderer traces by default block the same share of rays as the exact
// ribbons (Embree's normal-oriented curves): the meadow's gap fraction seen from straight above and
// at 45° agrees within a two-proportion z-test (|z| < 4; 20 000 rays each; nearer the horizon the
// 1 m patch blocks every ray and tells nothing).
TEST(TerrainRender, GrassStripsHaveTheExactRibbonsGapFraction) {
  const Scene strips_scene = grass_patch_scene(false), curves_scene = grass_patch_scene(true);
  const EmbreeScene strips(strips_scene), curves(curves_scene);
  for (const Vec3 d : {Vec3(0.0f, 0.0f, -1.0f), glm::normalize(Vec3(0.0f, 1.0f, -1.0f))}) {
    Pcg32 rng(7);
    int hit_strips = 0, hit_curves = 0;
    constexpr int kRays = 20000;
    for (int k = 0; k < kRays; ++k) {
      const Vec3 target(rng.uniform(-0.4f, 0.4f), rng.uniform(-0.4f, 0.4f), rng.uniform(0.0f, 0.2f));
      const Ray ray{target - 3.0f * d, d};
      RayHit h;
      hit_strips += strips.intersect(ray, &h);
      hit_curves += curves.intersect(ray, &h);
    }
    const double a = double(hit_strips) / kRays, b = double(hit_curves) / kRays, p = 0.5 * (a + b);
    const double z = (a - b) / std::sqrt(2.0 * p * (1.0 - p) / kRays);
    std::printf("[grass] direction (%.2f, %.2f, %.2f): strips block %.4f, curves %.4f, z %.2f\n", d.x, d.y, d.z, a, b,
                z);
    EXPECT_GT(a, 0.02);
    EXPECT_LT(a, 0.99);  // a gap fraction to compare, not a wall
    EXPECT_LT(std::abs(z), 4.0);
  }
}

}  // namespace
}  // namespace sylva
