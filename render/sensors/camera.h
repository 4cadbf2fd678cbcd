#pragma once
// Cameras: pinhole (lens_radius 0) and thin lens, looking from `position` at `target` with `up`
// (Z by default), vertical field of view in degrees. Raster space: x right, y down, pixel (0,0) is
// the top-left corner of the image.

#include "core/math.h"

#include <limits>

namespace sylva {

struct CameraDesc {
  Vec3 position{0.0f, -10.0f, 1.7f};
  Vec3 target{0.0f, 0.0f, 1.7f};
  Vec3 up{0.0f, 0.0f, 1.0f};
  float vfov_deg = 45.0f;
  float aperture_radius_m = 0.0f;  // 0 = pinhole
  float focus_distance_m = 0.0f;   // 0 = distance to target
};

struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit length
  float t_max = std::numeric_limits<float>::infinity();
};

class Camera {
 public:
  Camera() = default;
  Camera(const CameraDesc& desc, int width, int height);

  // A primary ray through raster position `film` (pixels) using lens sample `lens` in [0,1)².
  Ray generate_ray(Vec2 film, Vec2 lens) const;
  const CameraDesc& desc() const { return desc_; }

 private:
  CameraDesc desc_;
  Frame frame_;  // x right, y up, z forward (world)
  float tan_half_ = 0.5f;
  float aspect_ = 1.0f;
  float focus_ = 1.0f;
  int width_ = 1, height_ = 1;
};

}  // namespace sylva
