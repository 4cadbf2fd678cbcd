#include "render/sensors/camera.h"

#include "core/error.h"

namespace sylva {

Camera::Camera(const CameraDesc& desc, int width, int height) : desc_(desc) {
  const Vec3 forward = desc.target - desc.position;
  if (glm::length(forward) <= 0) throw Error("camera position and target coincide");
  const Vec3 z = glm::normalize(forward);
  Vec3 x = glm::cross(z, desc.up);
  if (glm::length(x) < 1e-6f) throw Error("camera up vector is parallel to the view direction");
  x = glm::normalize(x);
  frame_ = Frame{x, glm::cross(x, z), z};
  std::visit([&](auto& p) { p.prepare(width, height, glm::length(forward)); }, desc_.projection);
}

Ray Camera::generate_ray(Vec2 film, Vec2 lens) const {
  Vec3 origin_cam, dir_cam;
  std::visit([&](const auto& p) { p.camera_ray(film, lens, origin_cam, dir_cam); }, desc_.projection);
  Ray ray;
  ray.origin = desc_.position + frame_.to_world(origin_cam);
  ray.direction = glm::normalize(frame_.to_world(dir_cam));
  return ray;
}

}  // namespace sylva
