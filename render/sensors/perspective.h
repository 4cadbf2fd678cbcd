#pragma once
// Perspective projection: a pinhole (aperture_radius 0) or a thin lens focused at focus_distance
// (0: the distance to the camera's target), vertical field of view in degrees.
// Scene file: [camera] type = "perspective" (the default), vfov, aperture_radius, focus_distance.

#include "core/math.h"
#include "core/params.h"

#include <string_view>

namespace sylva {

struct PerspectiveProjection {
  static constexpr std::string_view kType = "perspective";

  float vfov_deg = 45.0f;
  float aperture_radius_m = 0.0f;  // 0 = pinhole
  float focus_distance_m = 0.0f;   // 0 = distance to target

  static PerspectiveProjection create(const Params& params);
  // Called once by Camera with the image size and the distance from the camera to its target.
  void prepare(int width, int height, float target_distance_m);
  // The ray through raster position `film` for lens sample `lens`, in camera space (x right, y up,
  // z forward); `direction` is not normalised.
  void camera_ray(Vec2 film, Vec2 lens, Vec3& origin, Vec3& direction) const;

 private:
  float tan_half_ = 0.5f, aspect_ = 1.0f, focus_ = 1.0f;
  float width_ = 1.0f, height_ = 1.0f;
};

}  // namespace sylva
