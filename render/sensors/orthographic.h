#pragma once
// Orthographic projection: parallel rays along the view direction from an image plane through the
// camera position, `width` metres wide (the height follows the image's aspect ratio) — a nadir view
// over a plot, or a measurement footprint.
// Scene file: [camera] type = "orthographic", width = METRES.

#include "core/math.h"
#include "core/params.h"

#include <string_view>

namespace sylva {

struct OrthographicProjection {
  static constexpr std::string_view kType = "orthographic";

  float width_m = 10.0f;  // footprint across the image

  static OrthographicProjection create(const Params& params);
  void prepare(int width, int height, float target_distance_m);
  void camera_ray(Vec2 film, Vec2 lens, Vec3& origin, Vec3& direction) const;

 private:
  float half_width_m_ = 5.0f, half_height_m_ = 5.0f;
  float width_ = 1.0f, height_ = 1.0f;
};

}  // namespace sylva
