#include "render/sensors/camera.h"

#include "core/error.h"
#include "core/sampling.h"

namespace sylva {

Camera::Camera(const CameraDesc& desc, int width, int height) : desc_(desc), width_(width), height_(height) {
  const Vec3 forward = desc.target - desc.position;
  if (glm::length(forward) <= 0) throw Error("camera position and target coincide");
  const Vec3 z = glm::normalize(forward);
  Vec3 x = glm::cross(z, desc.up);
  if (glm::length(x) < 1e-6f) throw Error("camera up vector is parallel to the view direction");
  x = glm::normalize(x);
  frame_ = Frame{x, glm::cross(x, z), z};
  if (!(desc.vfov_deg > 0 && desc.vfov_deg < 180))
    throw Error("camera vertical field of view must be in (0, 180) degrees");
  tan_half_ = std::tan(0.5f * radians(desc.vfov_deg));
  aspect_ = static_cast<float>(width) / static_cast<float>(height);
  focus_ = desc.focus_distance_m > 0 ? desc.focus_distance_m : glm::length(forward);
}

Ray Camera::generate_ray(Vec2 film, Vec2 lens) const {
  // Point on the plane of focus, in camera space (x right, y up, z forward).
  const float sx = (2.0f * film.x / static_cast<float>(width_) - 1.0f) * tan_half_ * aspect_;
  const float sy = (1.0f - 2.0f * film.y / static_cast<float>(height_)) * tan_half_;
  Vec3 dir_cam(sx, sy, 1.0f);
  Vec3 origin_cam(0.0f);
  if (desc_.aperture_radius_m > 0) {
    const Vec3 focus_point = dir_cam * focus_;
    const Vec2 d = desc_.aperture_radius_m * sample_uniform_disk(lens);
    origin_cam = Vec3(d.x, d.y, 0.0f);
    dir_cam = focus_point - origin_cam;
  }
  Ray ray;
  ray.origin = desc_.position + frame_.to_world(origin_cam);
  ray.direction = glm::normalize(frame_.to_world(dir_cam));
  return ray;
}

}  // namespace sylva
