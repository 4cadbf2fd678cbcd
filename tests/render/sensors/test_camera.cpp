// Cameras: the pinhole looks at its target; the thin lens focuses every lens sample of a film
// position onto one point of the plane of focus, and blurs points off it.

#include "core/rng.h"
#include "render/sensors/camera.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

TEST(Camera, PinholeCentreRayHitsTheTarget) {
  CameraDesc d;
  d.position = {1, -4, 2};
  d.target = {0.5f, 3, 1};
  const Camera cam(d, 200, 100);
  const Ray r = cam.generate_ray({100, 50}, {0.3f, 0.8f});
  EXPECT_NEAR(glm::length(r.origin - d.position), 0.0f, 1e-6f);
  const Vec3 to_target = glm::normalize(d.target - d.position);
  EXPECT_NEAR(glm::dot(r.direction, to_target), 1.0f, 1e-6f);
}

TEST(Camera, FieldOfViewAndOrientation) {
  CameraDesc d;
  d.position = {0, 0, 0};
  d.target = {0, 1, 0};
  std::get<PerspectiveProjection>(d.projection).vfov_deg = 60;
  const Camera cam(d, 100, 100);
  // Top edge of the image is 30° up; left edge is 30° left (square image); +Z is up in the image.
  const Ray top = cam.generate_ray({50, 0}, {});
  EXPECT_NEAR(degrees(std::asin(top.direction.z)), 30.0f, 1e-3f);
  const Ray left = cam.generate_ray({0, 50}, {});
  EXPECT_LT(left.direction.x, 0.0f);
  EXPECT_NEAR(degrees(std::atan2(-left.direction.x, left.direction.y)), 30.0f, 1e-3f);
}

TEST(Camera, ThinLensFocusesOnThePlaneOfFocus) {
  CameraDesc d;
  d.position = {0, -10, 1};
  d.target = {0, 0, 1};
  std::get<PerspectiveProjection>(d.projection).aperture_radius_m = 0.05f;
  std::get<PerspectiveProjection>(d.projection).focus_distance_m = 7.0f;
  const Camera cam(d, 64, 48);
  Pcg32 rng(3);
  const Vec2 film(13.3f, 40.2f);
  // All lens samples meet where the pinhole ray crosses the plane y = -3 (distance 7 along +Y).
  CameraDesc pin = d;
  std::get<PerspectiveProjection>(pin.projection).aperture_radius_m = 0;
  const Ray centre = Camera(pin, 64, 48).generate_ray(film, {});
  const Vec3 focus = centre.origin + centre.direction * (7.0f / centre.direction.y);
  float spread_at_focus = 0, spread_off_focus = 0;
  for (int i = 0; i < 200; ++i) {
    const Ray r = cam.generate_ray(film, {rng.uniform(), rng.uniform()});
    EXPECT_LE(glm::length(r.origin - d.position), 0.05f + 1e-6f);
    const Vec3 at = r.origin + r.direction * ((-3.0f - r.origin.y) / r.direction.y);
    spread_at_focus = std::max(spread_at_focus, glm::length(at - focus));
    const Vec3 off = r.origin + r.direction * ((5.0f - r.origin.y) / r.direction.y);
    const Vec3 off_centre = centre.origin + centre.direction * (15.0f / centre.direction.y);
    spread_off_focus = std::max(spread_off_focus, glm::length(off - off_centre));
  }
  EXPECT_LT(spread_at_focus, 1e-4f);
  EXPECT_GT(spread_off_focus, 0.02f);
}

TEST(Camera, OrthographicRaysAreParallelAndSpanTheFootprint) {
  CameraDesc d;
  d.position = {3, 4, 100};
  d.target = {3, 4, 0};
  d.up = {0, 1, 0};
  OrthographicProjection ortho;
  ortho.width_m = 20;
  d.projection = ortho;
  const Camera cam(d, 200, 100);
  const Ray left = cam.generate_ray({0, 50}, {0.3f, 0.7f});
  const Ray right = cam.generate_ray({200, 50}, {0.9f, 0.1f});
  const Ray top = cam.generate_ray({100, 0}, {});
  for (const Ray& r : {left, right, top}) {
    EXPECT_NEAR(r.direction.z, -1.0f, 1e-6f);
    EXPECT_NEAR(r.origin.z, 100.0f, 1e-4f);
  }
  // 20 m across, 10 m up-down (aspect 2:1); image right is world +X, image top world +Y here.
  EXPECT_NEAR(right.origin.x - left.origin.x, 20.0f, 1e-4f);
  EXPECT_NEAR(left.origin.x, -7.0f, 1e-4f);
  EXPECT_NEAR(top.origin.y, 9.0f, 1e-4f);
}

}  // namespace
}  // namespace sylva
