#include "render/sensors/orthographic.h"

#include "core/error.h"

namespace sylva {

OrthographicProjection OrthographicProjection::create(const Params& params) {
  OrthographicProjection p;
  p.width_m = params.real("width", p.width_m, 1e-6, 1e9);
  return p;
}

void OrthographicProjection::prepare(int width, int height, float) {
  if (!(width_m > 0)) throw Error("orthographic camera width must be positive");
  half_width_m_ = 0.5f * width_m;
  half_height_m_ = half_width_m_ * static_cast<float>(height) / static_cast<float>(width);
  width_ = static_cast<float>(width);
  height_ = static_cast<float>(height);
}

void OrthographicProjection::camera_ray(Vec2 film, Vec2, Vec3& origin, Vec3& direction) const {
  origin =
      Vec3((2.0f * film.x / width_ - 1.0f) * half_width_m_, (1.0f - 2.0f * film.y / height_) * half_height_m_, 0.0f);
  direction = Vec3(0.0f, 0.0f, 1.0f);
}

}  // namespace sylva
