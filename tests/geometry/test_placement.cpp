// Feature-map placement (geometry/placement.h, Weber & Penn §6): deterministic at any thread count,
// each bit only its species, the asked density (z-test), minimum spacing, trunks on the ground.

#include "core/error.h"
#include "core/rng.h"
#include "geometry/grass.h"
#include "geometry/placement.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>

namespace sylva {
namespace {

HeightField bumpy_terrain(Vec2 lo, Vec2 hi) {
  ProceduralTerrainParams p;
  p.size_m = hi - lo;
  p.centre_m = 0.5f * (lo + hi);
  p.resolution_m = 1.0f;
  p.relief_m = 6.0f;
  p.feature_size_m = 30.0f;
  return make_procedural_terrain(p);
}

// A map over [0, 200]² m: bit 0 on the west half, bit 1 on the east half, bit 2 everywhere; grass
// type 1 in the south, 2 in the north.
FeatureMap halves_map() {
  FeatureMap m;
  m.width = m.height = 100;
  m.min_m = Vec2(0.0f);
  m.max_m = Vec2(200.0f);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x) {
      const uint16_t tree = static_cast<uint16_t>((x < 50 ? 1u : 2u) | 4u);
      const uint16_t grass = static_cast<uint16_t>((y < 50 ? 2u : 1u) << kFeatureGrassShift);
      m.bits.push_back(tree | grass);
    }
  return m;
}

std::vector<SpeciesPlacement> three_species() {
  SpeciesPlacement a;
  a.bit = 0;
  a.density_per_ha = 150.0;
  a.min_spacing_m = 3.0f;
  a.scale_range = Vec2(0.8f, 1.2f);
  a.trunk_radius_m = {0.2f, 0.3f, 0.25f};
  SpeciesPlacement b = a;
  b.bit = 1;
  b.density_per_ha = 40.0;
  b.min_spacing_m = 5.0f;
  b.trunk_radius_m = {0.4f};
  SpeciesPlacement c = a;
  c.bit = 2;
  c.density_per_ha = 900.0;  // denser than 2·spacing cells allow: one tree per cell of its own spacing
  c.min_spacing_m = 2.5f;
  return {a, b, c};
}

TEST(Placement, DeterministicAtAnyThreadCount) {
  const FeatureMap map = halves_map();
  const HeightField terrain = bumpy_terrain(map.min_m, map.max_m);
  std::vector<PlacedTree> one, many;
  tbb::task_arena(1).execute([&] { one = place_trees(map, terrain, three_species(), 9); });
  tbb::task_arena(4).execute([&] { many = place_trees(map, terrain, three_species(), 9); });
  ASSERT_EQ(one.size(), many.size());
  ASSERT_GT(one.size(), 100u);
  for (size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].base_m, many[i].base_m);
    EXPECT_EQ(one[i].heading_rad, many[i].heading_rad);
    EXPECT_EQ(one[i].scale, many[i].scale);
    EXPECT_EQ(one[i].species, many[i].species);
    EXPECT_EQ(one[i].variant, many[i].variant);
  }
  EXPECT_NE(place_trees(map, terrain, three_species(), 10).front().base_m, one.front().base_m);
}

TEST(Placement, EachBitPlacesOnlyItsSpeciesWhereItIsSet) {
  const FeatureMap map = halves_map();
  const HeightField terrain = bumpy_terrain(map.min_m, map.max_m);
  const auto species = three_species();
  size_t per_species[3] = {0, 0, 0};
  for (const PlacedTree& t : place_trees(map, terrain, species, 1)) {
    ++per_species[t.species];
    EXPECT_TRUE(map.at(Vec2(t.base_m)) >> species[t.species].bit & 1u);
    if (t.species == 0) {
      EXPECT_LT(t.base_m.x, 100.0f);
    }
    if (t.species == 1) {
      EXPECT_GE(t.base_m.x, 100.0f);
    }
    EXPECT_LT(t.variant, species[t.species].trunk_radius_m.size());
    EXPECT_GE(t.scale, 0.8f);
    EXPECT_LE(t.scale, 1.2f);
  }
  for (size_t s = 0; s < 3; ++s) EXPECT_GT(per_species[s], 0u) << s;
}

TEST(Placement, DensityPerHectareWithinStatisticalTolerance) {
  FeatureMap map;
  map.width = map.height = 10;
  map.min_m = Vec2(0.0f);
  map.max_m = Vec2(300.0f);  // 9 ha
  map.bits.assign(100, 1u);
  const HeightField terrain = bumpy_terrain(map.min_m, map.max_m);
  SpeciesPlacement sp;
  sp.bit = 0;
  sp.min_spacing_m = 3.0f;
  sp.trunk_radius_m = {0.2f};
  for (const double density : {30.0, 120.0, 250.0}) {
    sp.density_per_ha = density;
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      const double n = static_cast<double>(place_trees(map, terrain, {sp}, seed).size());
      // Bernoulli thinning of cells 6 m wide (2·spacing): 2500 cells, p = density·36 m² / 1 ha.
      const double cells = 2500.0, p = density * 36.0 / 1e4;
      const double z = (n - cells * p) / std::sqrt(cells * p * (1.0 - p));
      EXPECT_LT(std::abs(z), 4.0) << density << " trees/ha, seed " << seed << ": " << n << " trees";
    }
  }
  // Denser than 2·spacing cells allow: one tree in every cell of the density's own spacing.
  sp.density_per_ha = 1e4 / 16.0;  // 4 m cells
  EXPECT_EQ(place_trees(map, terrain, {sp}, 1).size(), 75u * 75u);
  sp.density_per_ha = 1e4 / 8.0;  // closer than 3 m apart on average: impossible
  EXPECT_THROW(place_trees(map, terrain, {sp}, 1), Error);
}

TEST(Placement, MinimumSpacingHeldAndTrunksOnTheGround) {
  const FeatureMap map = halves_map();
  const HeightField terrain = bumpy_terrain(map.min_m, map.max_m);
  const auto species = three_species();
  const std::vector<PlacedTree> trees = place_trees(map, terrain, species, 5);
  for (size_t i = 0; i < trees.size(); ++i) {
    for (size_t j = i + 1; j < trees.size(); ++j)
      if (trees[i].species == trees[j].species) {
        EXPECT_GE(glm::length(Vec2(trees[i].base_m) - Vec2(trees[j].base_m)), species[trees[i].species].min_spacing_m);
      }
    // The base: the lowest terrain point under the trunk, within 1 cm (sampled densely here).
    const PlacedTree& t = trees[i];
    const float r = t.scale * species[t.species].trunk_radius_m[t.variant];
    float lowest = terrain_height(terrain, Vec2(t.base_m));
    const int n = 40;  // a grid of r/40 (under 1 cm) over the footprint
    for (int y = -n; y <= n; ++y)
      for (int x = -n; x <= n; ++x) {
        const Vec2 d = Vec2(static_cast<float>(x), static_cast<float>(y)) * (r / n);
        if (glm::length(d) <= r) lowest = std::min(lowest, terrain_height(terrain, Vec2(t.base_m) + d));
      }
    EXPECT_LE(t.base_m.z, lowest + 1e-5f);
    EXPECT_NEAR(t.base_m.z, lowest, 0.01f);
    EXPECT_LE(t.base_m.z, terrain_height(terrain, Vec2(t.base_m)) + 1e-5f);
  }
}

TEST(Placement, GrassPatchesFollowTheGrassBits) {
  const FeatureMap map = halves_map();
  const HeightField terrain = bumpy_terrain(map.min_m, map.max_m);
  const std::vector<PlacedPatch> patches = place_grass_patches(map, terrain, {2.0f, 4.0f}, 3);
  size_t per_type[3] = {0, 0, 0};
  for (const PlacedPatch& p : patches) {
    ASSERT_GE(p.grass_type, 1);
    ASSERT_LE(p.grass_type, 2);
    ++per_type[p.grass_type];
    EXPECT_EQ(grass_type(map.at(Vec2(p.centre_m))), p.grass_type);
    EXPECT_NEAR(p.centre_m.z, terrain_height(terrain, Vec2(p.centre_m)), 1e-5f);
  }
  // Half the area each: 100 × 50 cells of 2 m, 50 × 25 of 4 m (jittered centres: ± a few per row).
  EXPECT_NEAR(static_cast<double>(per_type[1]), 5000.0, 200.0);
  EXPECT_NEAR(static_cast<double>(per_type[2]), 1250.0, 100.0);
}

TEST(Grass, PatchBladesRootedInTheSquare) {
  GrassParams g;
  g.patch_size_m = 1.5f;
  g.density_per_m2 = 400.0f;
  const CurveSet c = make_grass_patch(g, 2);
  ASSERT_EQ(c.size(), 900u);
  ASSERT_EQ(c.normals.size(), c.points.size());
  for (size_t i = 0; i < c.size(); ++i) {
    const Vec4 base = c.points[4 * i], tip = c.points[4 * i + 3];
    EXPECT_EQ(base.z, 0.0f);
    EXPECT_LE(std::abs(base.x), 0.75f);
    EXPECT_LE(std::abs(base.y), 0.75f);
    EXPECT_GT(tip.z, 0.0f);
    EXPECT_NEAR(base.w, 0.5f * g.width_m, 1e-7f);
    EXPECT_LT(tip.w, base.w);
    // Each control polygon's legs are a third of the length: the blade is 0.2–0.4 m long.
    float length = 0.0f;
    for (int k = 0; k < 3; ++k) length += glm::length(Vec3(c.points[4 * i + k + 1]) - Vec3(c.points[4 * i + k]));
    EXPECT_GE(length, 0.2f - 1e-4f);
    EXPECT_LE(length, 0.4f + 1e-4f);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(glm::length(c.normals[4 * i + k]), 1.0f, 1e-5f);
  }
  EXPECT_EQ(make_grass_patch(g, 2).points, c.points);
}

// The quad strips the renderer traces (tessellate_ribbons): each blade's strip starts at its base
// control point and ends at its tip, spans the blade's width across its normal, and its area — each
// quad's two triangles (q0, q1, q3) and (q2, q3, q1), as Embree splits it — converges to the
// ribbon's, ∫ 2 r(t) |P'(t)| dt, estimated here with a fine midpoint rule.
TEST(Grass, RibbonStripsFollowTheBladesAndKeepTheirArea) {
  GrassParams g;
  g.patch_size_m = 0.5f;
  g.density_per_m2 = 400.0f;
  g.bend = 0.8f;
  const CurveSet c = make_grass_patch(g, 5);
  ASSERT_GT(c.size(), 50u);
  const auto strip_area = [&](int segments, std::vector<Vec3>* points) {
    std::vector<glm::uvec4> quads;
    points->clear();
    tessellate_ribbons(c, segments, *points, quads);
    EXPECT_EQ(quads.size(), c.size() * size_t(segments));
    EXPECT_EQ(points->size(), c.size() * 2 * size_t(segments + 1));
    const auto triangle_area = [&](uint32_t a, uint32_t b, uint32_t d) {
      return 0.5 * glm::length(glm::cross((*points)[b] - (*points)[a], (*points)[d] - (*points)[a]));
    };
    double area = 0.0;
    for (const glm::uvec4& q : quads) {
      EXPECT_LT(std::max({q.x, q.y, q.z, q.w}), points->size());
      area += triangle_area(q.x, q.y, q.w) + triangle_area(q.z, q.w, q.y);
    }
    return area;
  };
  std::vector<Vec3> points;
  const double six = strip_area(6, &points);
  const size_t stride = 2 * 7;
  for (size_t k = 0; k < c.size(); ++k) {
    const Vec4 base = c.points[4 * k], tip = c.points[4 * k + 3];
    const Vec3 mid_base = 0.5f * (points[stride * k] + points[stride * k + 1]);
    const Vec3 mid_tip = 0.5f * (points[stride * k + stride - 2] + points[stride * k + stride - 1]);
    EXPECT_LT(glm::length(mid_base - Vec3(base)), 1e-6f);
    EXPECT_LT(glm::length(mid_tip - Vec3(tip)), 1e-6f);
    EXPECT_NEAR(glm::length(points[stride * k + 1] - points[stride * k]), 2.0f * base.w, 1e-6f);
    // The width runs across the blade's normal.
    EXPECT_LT(std::abs(glm::dot(glm::normalize(points[stride * k + 1] - points[stride * k]), c.normals[4 * k])), 1e-3f);
  }
  double exact = 0.0;
  constexpr int kSteps = 4000;
  for (size_t k = 0; k < c.size(); ++k) {
    const Vec4* p = &c.points[4 * k];
    for (int i = 0; i < kSteps; ++i) {
      const double t = (i + 0.5) / kSteps, s = 1.0 - t;
      const double r = s * s * s * p[0].w + 3 * s * s * t * p[1].w + 3 * s * t * t * p[2].w + t * t * t * p[3].w;
      const Vec3 d = float(3 * s * s) * Vec3(p[1] - p[0]) + float(6 * s * t) * Vec3(p[2] - p[1]) +
                     float(3 * t * t) * Vec3(p[3] - p[2]);
      exact += 2.0 * r * glm::length(d) / kSteps;
    }
  }
  EXPECT_NEAR(six, exact, 0.01 * exact);
  EXPECT_LT(std::abs(strip_area(24, &points) - exact), std::abs(six - exact) + 1e-9);
  EXPECT_THROW(strip_area(0, &points), Error);
}

}  // namespace
}  // namespace sylva
