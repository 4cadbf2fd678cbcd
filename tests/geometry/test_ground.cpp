// Ground queries (geometry/ground.h): the highest surface on a vertical line through placed meshes.

#include "geometry/ground.h"
#include "geometry/primitives.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

namespace sylva {
namespace {

TEST(Ground, HighestSurfaceOnAVerticalLineThroughPlacedMeshes) {
  const TriangleMesh plane = make_plane(20, 20);
  const TriangleMesh box = make_box(Vec3(2, 2, 1));  // base on z = 0
  // A plane tilted 10° about X (z = y·tan 10°), and a box raised by 3 m at (5, 5).
  const Mat4 tilt = glm::rotate(Mat4(1.0f), glm::radians(10.0f), Vec3(1, 0, 0));
  const Mat4 raised = glm::translate(Mat4(1.0f), Vec3(5, 5, 3));
  const std::vector<PlacedMesh> ground{{&plane, tilt, placed_bounds(plane, tilt)},
                                       {&box, raised, placed_bounds(box, raised)}};
  const std::optional<float> on_plane = highest_surface_z(ground, Vec2(-3, 4));
  ASSERT_TRUE(on_plane);
  EXPECT_NEAR(*on_plane, 4 * std::tan(glm::radians(10.0f)), 1e-5f);
  // Over the box its top (3 + 1) is higher than the plane under it.
  const std::optional<float> on_box = highest_surface_z(ground, Vec2(5.5f, 4.5f));
  ASSERT_TRUE(on_box);
  EXPECT_NEAR(*on_box, 4.0f, 1e-6f);
  // Beyond every mesh: nothing.
  EXPECT_FALSE(highest_surface_z(ground, Vec2(50, 0)));
  EXPECT_FALSE(highest_surface_z({}, Vec2(0, 0)));
}

TEST(Ground, PlacedBoundsHoldTheTransformedMesh) {
  const TriangleMesh box = make_box(Vec3(2, 1, 1));
  const Mat4 m = glm::rotate(glm::translate(Mat4(1.0f), Vec3(1, 2, 3)), glm::radians(90.0f), Vec3(0, 0, 1));
  const Bounds3 b = placed_bounds(box, m);
  for (const Vec3& p : box.positions) {
    const Vec3 w(m * Vec4(p, 1.0f));
    for (int i = 0; i < 3; ++i) {
      EXPECT_GE(w[i], b.lo[i] - 1e-5f);
      EXPECT_LE(w[i], b.hi[i] + 1e-5f);
    }
  }
  EXPECT_NEAR(b.hi.x - b.lo.x, 1.0f, 1e-5f);  // the 2 m side turned to run along y
  EXPECT_NEAR(b.hi.y - b.lo.y, 2.0f, 1e-5f);
}

}  // namespace
}  // namespace sylva
