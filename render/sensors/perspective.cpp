#include "render/sensors/perspective.h"

#include "core/error.h"
#include "core/sampling.h"

namespace sylva {

PerspectiveProjection PerspectiveProjection::create(const Params& params) {
  PerspectiveProjection p;
  p.vfov_deg = params.real("vfov", p.vfov_deg, 0.01, 179.0);
  p.aperture_radius_m = params.real("aperture_radius", p.aperture_radius_m, 0.0, 100.0);
  p.focus_distance_m = params.real("focus_distance", p.focus_distance_m, 0.0, 1e6);
  return p;
}

void PerspectiveProjection::prepare(int width, int height, float target_distance_m) {
  if (!(vfov_deg > 0 && vfov_deg < 180)) throw Error("camera vertical field of view must be in (0, 180) degrees");
  tan_half_ = std::tan(0.5f * radians(vfov_deg));
  aspect_ = static_cast<float>(width) / static_cast<float>(height);
  focus_ = focus_distance_m > 0 ? focus_distance_m : target_distance_m;
  width_ = static_cast<float>(width);
  height_ = static_cast<float>(height);
}

void PerspectiveProjection::camera_ray(Vec2 film, Vec2 lens, Vec3& origin, Vec3& direction) const {
  // Point on the plane of focus, in camera space.
  const float sx = (2.0f * film.x / width_ - 1.0f) * tan_half_ * aspect_;
  const float sy = (1.0f - 2.0f * film.y / height_) * tan_half_;
  direction = Vec3(sx, sy, 1.0f);
  origin = Vec3(0.0f);
  if (aperture_radius_m > 0) {
    const Vec3 focus_point = direction * focus_;
    const Vec2 d = aperture_radius_m * sample_uniform_disk(lens);
    origin = Vec3(d.x, d.y, 0.0f);
    direction = focus_point - origin;
  }
}

}  // namespace sylva
