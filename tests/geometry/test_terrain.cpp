// Terrain (geometry/terrain.h): raster heights reproduced at pixel centres, the height query exact
// to the meshed triangles, a watertight mesh, reduced resolution and procedural terrains.

#include "core/rng.h"
#include "geometry/terrain.h"

#include <gtest/gtest.h>

#include <map>
#include <utility>

namespace sylva {
namespace {

std::vector<float> random_raster(int w, int h, uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<float> v(static_cast<size_t>(w) * h);
  for (float& z : v) z = rng.uniform(-3.0f, 12.0f);
  return v;
}

// The height of `mesh` at (x, y) by brute force: the triangle whose xy-projection contains it.
std::optional<float> mesh_height(const TriangleMesh& mesh, Vec2 q) {
  for (const glm::uvec3& t : mesh.triangles) {
    const Vec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
    const float d = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    const float u = ((q.x - a.x) * (c.y - a.y) - (c.x - a.x) * (q.y - a.y)) / d;
    const float v = ((b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y)) / d;
    if (u >= -1e-6f && v >= -1e-6f && u + v <= 1.0f + 1e-6f) return a.z + u * (b.z - a.z) + v * (c.z - a.z);
  }
  return std::nullopt;
}

TEST(Terrain, RasterHeightsAtPixelCentres) {
  const int w = 7, h = 5;
  const std::vector<float> raster = random_raster(w, h, 1);
  const Vec2 sw(100.0f, -40.0f);  // centre of the south-west pixel
  const float px = 2.0f;
  const HeightField f = resample_height_raster(raster, w, h, sw, px, 1);
  ASSERT_EQ(f.width, w);
  ASSERT_EQ(f.height, h);
  const TriangleMesh mesh = make_terrain_mesh(f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Raster row y counts from the north edge.
      const Vec2 centre = sw + px * Vec2(static_cast<float>(x), static_cast<float>(h - 1 - y));
      const float expected = raster[static_cast<size_t>(y) * w + x];
      EXPECT_NEAR(terrain_height(f, centre), expected, 1e-5f) << x << "," << y;
      const auto on_mesh = mesh_height(mesh, centre);
      ASSERT_TRUE(on_mesh.has_value());
      EXPECT_NEAR(*on_mesh, expected, 1e-4f);
    }
}

TEST(Terrain, HeightQueryIsExactToTheMeshedTriangles) {
  const int w = 6, h = 8;
  const HeightField f = resample_height_raster(random_raster(w, h, 2), w, h, Vec2(-5.0f, 3.0f), 1.5f, 1);
  const TriangleMesh mesh = make_terrain_mesh(f);
  Pcg32 rng(3);
  for (int k = 0; k < 500; ++k) {
    const Vec2 q(rng.uniform(f.min_m.x, f.max_m().x), rng.uniform(f.min_m.y, f.max_m().y));
    const auto expected = mesh_height(mesh, q);
    ASSERT_TRUE(expected.has_value());
    EXPECT_NEAR(terrain_height(f, q), *expected, 1e-4f) << q.x << "," << q.y;
  }
}

TEST(Terrain, MeshIsWatertightWithSmoothUnitNormals) {
  const int w = 9, h = 6;
  const HeightField f = resample_height_raster(random_raster(w, h, 4), w, h, Vec2(0.0f), 1.0f, 1);
  const TriangleMesh mesh = make_terrain_mesh(f);
  ASSERT_EQ(mesh.positions.size(), static_cast<size_t>(w * h));
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const glm::uvec3& t : mesh.triangles) {
    const uint32_t v[3] = {t.x, t.y, t.z};
    for (int e = 0; e < 3; ++e) ++edges[std::minmax(v[e], v[(e + 1) % 3])];
    // Counter-clockwise seen from above: the face normal points up.
    const Vec3 n = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
    EXPECT_GT(n.z, 0.0f);
  }
  int boundary = 0;
  for (const auto& [edge, count] : edges) {
    EXPECT_LE(count, 2);
    boundary += count == 1;
  }
  // Only the outline is open: every interior edge has two triangles (no cracks, no T-junctions).
  EXPECT_EQ(boundary, 2 * (w - 1) + 2 * (h - 1));
  for (const Vec3& n : mesh.normals) {
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
    EXPECT_GT(n.z, 0.0f);
  }
}

TEST(Terrain, StepKeepsEveryStepthPixel) {
  const int w = 9, h = 7;
  const std::vector<float> raster = random_raster(w, h, 5);
  const HeightField f = resample_height_raster(raster, w, h, Vec2(0.0f), 1.0f, 2);
  ASSERT_EQ(f.width, 5);
  ASSERT_EQ(f.height, 4);
  EXPECT_FLOAT_EQ(f.spacing_m.x, 2.0f);
  for (int j = 0; j < f.height; ++j)
    for (int i = 0; i < f.width; ++i)
      EXPECT_NEAR(f.at(i, j), raster[static_cast<size_t>(h - 1 - 2 * j) * w + 2 * i], 1e-5f);
  // A step that does not divide the raster still spans the same pixel centres.
  const HeightField g = resample_height_raster(raster, w, h, Vec2(0.0f), 1.0f, 3);
  EXPECT_NEAR(g.max_m().x, 8.0f, 1e-5f);
  EXPECT_NEAR(g.max_m().y, 6.0f, 1e-5f);
}

TEST(Terrain, LowestPointUnderAFootprint) {
  // Slopes up to about 2 (steeper than any forest floor), so a 2 mm brute-force grid over the disc
  // finds the lowest point to within 4 mm.
  const int w = 12, h = 12;
  std::vector<float> raster = random_raster(w, h, 6);
  for (float& z : raster) z *= 0.06f;
  const HeightField f = resample_height_raster(raster, w, h, Vec2(0.0f), 0.5f, 1);
  Pcg32 rng(7);
  for (int k = 0; k < 20; ++k) {
    const Vec2 c(rng.uniform(1.0f, 4.5f), rng.uniform(1.0f, 4.5f));
    const float r = rng.uniform(0.05f, 0.6f);
    const float lowest = terrain_min_height(f, c, r);
    float brute = terrain_height(f, c);
    const int n = static_cast<int>(r / 0.002f);
    for (int y = -n; y <= n; ++y)
      for (int x = -n; x <= n; ++x) {
        const Vec2 d = Vec2(static_cast<float>(x), static_cast<float>(y)) * (r / static_cast<float>(n));
        if (glm::length(d) <= r) brute = std::min(brute, terrain_height(f, c + d));
      }
    EXPECT_LE(lowest, brute + 1e-5f);
    EXPECT_GE(lowest, brute - 0.005f);
  }
}

TEST(Terrain, ProceduralIsDeterministicAndSpansTheRelief) {
  ProceduralTerrainParams p;
  p.size_m = Vec2(100.0f, 60.0f);
  p.resolution_m = 2.0f;
  p.relief_m = 7.0f;
  const HeightField a = make_procedural_terrain(p), b = make_procedural_terrain(p);
  EXPECT_EQ(a.heights, b.heights);
  EXPECT_EQ(a.width, 51);
  EXPECT_EQ(a.height, 31);
  EXPECT_NEAR(a.min_m.x, -50.0f, 1e-5f);
  EXPECT_FLOAT_EQ(*std::min_element(a.heights.begin(), a.heights.end()), 0.0f);
  EXPECT_NEAR(*std::max_element(a.heights.begin(), a.heights.end()), 7.0f, 1e-4f);
  p.seed = 2;
  EXPECT_NE(make_procedural_terrain(p).heights, a.heights);
  p.seed = 1;
  p.ridged = true;
  EXPECT_NE(make_procedural_terrain(p).heights, a.heights);
}

}  // namespace
}  // namespace sylva
