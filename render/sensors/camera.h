#pragma once
// Cameras: a view frame (looking from `position` at `target` with `up`, Z by default) and a
// projection chosen from a registry. Raster space: x right, y down, pixel (0,0) is the top-left
// corner of the image.
//
// Projections are a closed set open to extension; each lives in its own file pair and provides
//   static constexpr std::string_view kType;   // [camera] type = "..."
//   static P create(const Params&);            // reads its own parameters
//   void prepare(int width, int height, float target_distance_m);
//   void camera_ray(Vec2 film, Vec2 lens, Vec3& origin, Vec3& direction) const;  // camera space
// Adding a sensor = its files + one entry in the `Projection` variant below.

#include "core/math.h"
#include "render/sensors/orthographic.h"
#include "render/sensors/perspective.h"

#include <limits>
#include <variant>

namespace sylva {

// The registered projections.
using Projection = std::variant<PerspectiveProjection, OrthographicProjection>;

struct CameraDesc {
  Vec3 position{0.0f, -10.0f, 1.7f};
  Vec3 target{0.0f, 0.0f, 1.7f};
  Vec3 up{0.0f, 0.0f, 1.0f};
  Projection projection = PerspectiveProjection{};
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
};

}  // namespace sylva
