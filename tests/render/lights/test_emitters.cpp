// Emitters as lights (render/lights/emitters.h): the triangle chosen in proportion to area × power
// (χ²), points uniform over each triangle (χ² over its barycentric halves), the density a hit reads
// back equal to the sample's, normals as hits decode them under instance transforms, and what is
// not sampled (other kinds, non-emitting materials, cyclic plots).

#include "core/rng.h"
#include "core/statistics.h"
#include "geometry/primitives.h"
#include "render/lights/emitters.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

namespace sylva {
namespace {

const double kEmittersAlpha = sidak_alpha(0.01, 2);  // two χ² tests in this file

// Two copies of an emissive quad (one scaled 2 × 1 and mirrored, det < 0), a brighter two-sided
// emissive box, and a diffuse plane that does not emit.
Scene emitters_test_scene() {
  Scene s;
  const uint32_t lamp = s.add_material(
      "lamp", make_emissive("lamp", DenseSpectrum::constant(1.0f), DenseSpectrum::constant(0.0f), false));
  const uint32_t bright = s.add_material(
      "bright", make_emissive("bright", DenseSpectrum::constant(3.0f), DenseSpectrum::constant(0.5f), true));
  const uint32_t grey = s.add_material("grey", make_diffuse("grey", DenseSpectrum::constant(0.5f)));
  const uint32_t quad = s.add_prototype(Prototype{"quad", make_plane(1, 1), lamp, {}, 0, {}, {}, {}, 0, {}, 0});
  const uint32_t box = s.add_prototype(Prototype{"box", make_box(Vec3(0.5f)), bright, {}, 0, {}, {}, {}, 0, {}, 0});
  const uint32_t floor = s.add_prototype(Prototype{"floor", make_plane(10, 10), grey, {}, 0, {}, {}, {}, 0, {}, 0});
  s.instances.push_back({floor, Mat4(1.0f), 0});
  s.instances.push_back({quad, glm::translate(Mat4(1.0f), Vec3(0, 0, 2)), 0});
  s.instances.push_back({quad, glm::scale(glm::translate(Mat4(1.0f), Vec3(3, 0, 2)), Vec3(2, -1, 1)), 0});
  s.instances.push_back({box, glm::translate(Mat4(1.0f), Vec3(-3, 0, 0)), 0});
  return s;
}

RayHit emitter_triangle_hit(uint32_t instance, uint32_t primitive) {
  RayHit hit;
  hit.instance = instance;
  hit.kind = PrimitiveKind::kTriangles;
  hit.primitive = primitive;
  return hit;
}

TEST(Emitters, TrianglesChosenByAreaTimesPower) {
  const Scene s = emitters_test_scene();
  const EmitterLights lights(s);
  // 2 + 2 quad triangles and 12 box triangles; the floor does not emit.
  ASSERT_EQ(lights.size(), 16u);
  // Weights: quad 1 m² × π·∫1, mirrored quad 2 m² × the same, box 6 × 0.25 m² × 2 faces × π·∫3.
  const float p_quad = emitted_power_w_m2(s.materials[0]), p_box = emitted_power_w_m2(s.materials[1]);
  EXPECT_NEAR(p_box / p_quad, 6.0f, 1e-4f);
  std::vector<double> expected_weight;
  for (int t = 0; t < 2; ++t) expected_weight.push_back(0.5 * p_quad);
  for (int t = 0; t < 2; ++t) expected_weight.push_back(1.0 * p_quad);
  for (int t = 0; t < 12; ++t) expected_weight.push_back(0.125 * p_box);
  double total = 0;
  for (const double w : expected_weight) total += w;
  // Which sample lands on which (instance, triangle): bins in table order.
  const auto bin = [](const HitContext& c) {
    return c.instance == 1 ? c.primitive : c.instance == 2 ? 2 + c.primitive : 4 + c.primitive;
  };
  constexpr int kSamples = 200000;
  std::vector<double> observed(16, 0.0), expected(16, 0.0);
  Pcg32 rng(7);
  for (int i = 0; i < kSamples; ++i) {
    const float u_select = rng.uniform();
    const Vec2 u = uniform2(rng);
    const EmitterPoint e = lights.sample(u_select, u);
    observed[bin(e.ctx)] += 1;
    // The density a hit on that triangle reads back is the sample's.
    EXPECT_FLOAT_EQ(lights.pdf_area(emitter_triangle_hit(e.ctx.instance, e.ctx.primitive)), e.pdf_area);
  }
  for (size_t b = 0; b < 16; ++b) expected[b] = kSamples * expected_weight[b] / total;
  const Chi2Result r = chi2_test(observed, expected);
  EXPECT_GT(r.p_value, kEmittersAlpha) << "chi2 " << r.statistic << " dof " << r.dof;
  // The density per area integrates to 1 over the emitters: Σ P(triangle) = Σ pdf_area · area.
  double sum = 0;
  for (uint32_t t = 0; t < 2; ++t) sum += lights.pdf_area(emitter_triangle_hit(1, t)) * 0.5;
  for (uint32_t t = 0; t < 2; ++t) sum += lights.pdf_area(emitter_triangle_hit(2, t)) * 1.0;
  for (uint32_t t = 0; t < 12; ++t) sum += lights.pdf_area(emitter_triangle_hit(3, t)) * 0.125;
  EXPECT_NEAR(sum, 1.0, 1e-4);
}

TEST(Emitters, PointsUniformOverATriangleWithHitNormals) {
  // One triangle (0,0,0), (1,0,0), (0,1,0) under a mirroring transform: points uniform over it (χ²
  // over a 4 × 4 grid of its bounding square, cells weighted by their area inside), the normal a
  // hit decodes (the object normal +Z through normal_from_object), barycentric uv.
  Scene s;
  const uint32_t lamp = s.add_material(
      "lamp", make_emissive("lamp", DenseSpectrum::constant(1.0f), DenseSpectrum::constant(0.0f), false));
  Prototype p;
  p.triangles.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  p.triangles.triangles = {glm::uvec3(0, 1, 2)};
  p.triangle_material = lamp;
  const Instance mirrored{s.add_prototype(p), glm::scale(Mat4(1.0f), Vec3(1, 1, -1)), 5};
  s.instances.push_back(mirrored);
  const EmitterLights lights(s);
  ASSERT_EQ(lights.size(), 1u);
  const Vec3 expected_normal = glm::normalize(normal_from_object(mirrored) * Vec3(0, 0, 1));
  constexpr int kGrid = 4, kSamples = 100000;
  std::vector<double> observed(kGrid * kGrid, 0.0), expected(kGrid * kGrid, 0.0);
  Pcg32 rng(11);
  for (int i = 0; i < kSamples; ++i) {
    const float u_select = rng.uniform();
    const Vec2 u = uniform2(rng);
    const EmitterPoint e = lights.sample(u_select, u);
    ASSERT_NEAR(e.pdf_area, 2.0f, 1e-5f);  // 1 / area
    ASSERT_LT(glm::length(e.ctx.ng - expected_normal), 1e-6f);
    ASSERT_NEAR(e.ctx.p.x, e.ctx.uv.x, 1e-6f);
    ASSERT_NEAR(e.ctx.p.y, e.ctx.uv.y, 1e-6f);
    ASSERT_EQ(e.ctx.object_id, 5u);
    const int cx = std::min(kGrid - 1, static_cast<int>(e.ctx.p.x * kGrid));
    const int cy = std::min(kGrid - 1, static_cast<int>(e.ctx.p.y * kGrid));
    observed[cy * kGrid + cx] += 1;
  }
  for (int cy = 0; cy < kGrid; ++cy)
    for (int cx = 0; cx < kGrid; ++cx) {
      // Area of the cell [cx, cx+1] × [cy, cy+1] / kGrid below x + y = 1, in units of a cell.
      const int s_lo = cx + cy;
      const double inside = s_lo + 2 <= kGrid ? 1.0 : s_lo + 1 == kGrid ? 0.5 : 0.0;
      expected[cy * kGrid + cx] = kSamples * inside / (kGrid * kGrid / 2.0);
    }
  const Chi2Result r = chi2_test(observed, expected);
  EXPECT_GT(r.p_value, kEmittersAlpha) << "chi2 " << r.statistic << " dof " << r.dof;
}

TEST(Emitters, WhatIsNotSampled) {
  Scene s = emitters_test_scene();
  const EmitterLights lights(s);
  EXPECT_EQ(lights.pdf_area(emitter_triangle_hit(0, 0)), 0.0f);  // the floor does not emit
  RayHit leaf = emitter_triangle_hit(1, 0);
  leaf.kind = PrimitiveKind::kLeafQuads;
  EXPECT_EQ(lights.pdf_area(leaf), 0.0f);  // another kind on an emitting instance
  // Leaf quads in an emissive material: not sampled (their emission counts at hits only).
  Scene leaves;
  const uint32_t lamp = leaves.add_material(
      "lamp", make_emissive("lamp", DenseSpectrum::constant(1.0f), DenseSpectrum::constant(0.0f), false));
  Prototype p;
  p.leaves = make_leaf_cloud(LeafCloudParams{}, 3);
  p.leaf_material = lamp;
  leaves.instances.push_back({leaves.add_prototype(p), Mat4(1.0f), 0});
  EXPECT_TRUE(EmitterLights(leaves).empty());
  // A cyclic plot: not sampled.
  s.plot.defined = true;
  s.plot.cyclic = true;
  s.plot.lo = Vec2(-10.0f);
  s.plot.hi = Vec2(10.0f);
  EXPECT_TRUE(EmitterLights(s).empty());
  // No emitter at all.
  Scene dark;
  dark.add_material("grey", make_diffuse("grey", DenseSpectrum::constant(0.5f)));
  dark.instances.push_back(
      {dark.add_prototype(Prototype{"floor", make_plane(1, 1), 0, {}, 0, {}, {}, {}, 0, {}, 0}), Mat4(1.0f), 0});
  EXPECT_TRUE(EmitterLights(dark).empty());
}

}  // namespace
}  // namespace sylva
