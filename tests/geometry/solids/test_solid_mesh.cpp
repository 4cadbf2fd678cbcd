// Polygonising half-space solids (geometry/solids/solid_mesh.h, `sylva tree --obj`): the bare
// polytope's exact faces, and the displaced solid's marching tetrahedra — closed (every edge in two
// triangles), vertices on the surface within the grid's Lipschitz bound, outward orientation, and
// the enclosed volume of the solid D ≤ 0.

#include "core/rng.h"
#include "geometry/solids/solid_mesh.h"

#include <gtest/gtest.h>

#include <map>

namespace sylva {
namespace {

HalfSpaceSolid box_solid(float displacement) {
  HalfSpaceSolid s;
  for (int axis = 0; axis < 3; ++axis)
    for (const float sign : {-1.0f, 1.0f}) {
      Vec3 n(0.0f);
      n[axis] = sign;
      s.planes.push_back(HalfSpace{n, axis == 2 ? 3.0f : 2.0f});
    }
  s.planes.push_back(HalfSpace{glm::normalize(Vec3(1, 1, 1)), 3.0f});
  s.displacement_m = displacement;
  s.displacement = FbmParams{0.7f, 2.0f, 4, 1.5f, 5};
  finish_solid(s);
  return s;
}

double mesh_volume(const TriangleMesh& m) {
  double v = 0.0;
  for (const glm::uvec3& t : m.triangles)
    v +=
        glm::dot(glm::dvec3(m.positions[t.x]), glm::cross(glm::dvec3(m.positions[t.y]), glm::dvec3(m.positions[t.z]))) /
        6.0;
  return v;
}

TEST(SolidMesh, ClosedOnTheSurfaceWithTheSolidsVolume) {
  const HalfSpaceSolid s = box_solid(0.4f);
  const int cells = 64;
  const TriangleMesh m = solid_surface_mesh(s, cells);
  ASSERT_GT(m.triangles.size(), 1000u);
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const glm::uvec3& t : m.triangles)
    for (const auto& [a, b] : {std::pair{t.x, t.y}, {t.y, t.z}, {t.z, t.x}}) ++edges[{std::min(a, b), std::max(a, b)}];
  size_t open = 0;
  for (const auto& [e, n] : edges) open += n != 2;
  EXPECT_EQ(open, 0u);
  const Vec3 extent = s.bounds.hi - s.bounds.lo;
  const float h = std::max({extent.x, extent.y, extent.z}) / cells;
  for (const Vec3& p : m.positions) ASSERT_LE(std::abs(solid_distance(s, p)), s.lipschitz * h);
  // Monte Carlo volume of D ≤ 0 in the bounds.
  Pcg32 rng(3);
  const int n = 400000;
  int inside = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = s.bounds.lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * extent;
    inside += solid_distance(s, p) <= 0.0f;
  }
  const double mc = static_cast<double>(inside) / n * extent.x * extent.y * extent.z;
  EXPECT_NEAR(mesh_volume(m), mc, 0.02 * mc);  // positive: triangles face outwards
}

TEST(SolidMesh, BarePolytopeIsItsExactFaces) {
  const HalfSpaceSolid s = box_solid(0.0f);
  const TriangleMesh m = solid_surface_mesh(s);
  EXPECT_NEAR(mesh_volume(m), polytope_volume(polytope_faces(s.planes, 100.0f)), 1e-4);
  for (const Vec3& p : m.positions) EXPECT_NEAR(polytope_distance(s.planes, p), 0.0f, 1e-5f);
}

}  // namespace
}  // namespace sylva
