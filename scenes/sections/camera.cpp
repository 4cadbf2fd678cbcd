#include "scenes/sections/camera.h"

#include "core/registry.h"

#include <fmt/core.h>

namespace sylva {

void parse_camera(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("camera");
  CameraDesc& c = b.scene().camera;
  c.position = t->vec3("position", c.position);
  c.target = t->vec3("target", c.target);
  c.up = t->vec3("up", c.up);
  const std::string type = t->string("type", "perspective");
  std::optional<Projection> projection = create_registered<Projection>(type, *t);
  if (!projection)
    t->fail("type", fmt::format("camera type must be {}, not \"{}\"", registered_names<Projection>(), type));
  c.projection = *projection;
  // `above_terrain = true`: position and target z are heights above the [terrain] surface under
  // them (an eye-height camera on any terrain); applied once the terrain is built.
  b.camera_above_terrain = t->boolean("above_terrain", false);
  if (b.camera_above_terrain && !root.has("terrain")) t->fail("above_terrain", "above_terrain needs a [terrain]");
  t->check_unused();
  // Single-precision ray arithmetic: beyond this distance from the origin the view frame (and
  // every hit point) loses its precision; docs/limits.md.
  for (const char* key : {"position", "target"}) {
    const Vec3& v = key[0] == 'p' ? c.position : c.target;
    if (!(glm::max(glm::abs(v.x), glm::max(glm::abs(v.y), glm::abs(v.z))) <= kMaxSceneCoordinate_m))
      t->fail(key, fmt::format("camera {} must lie within {:g} m of the origin on every axis (docs/limits.md)", key,
                               kMaxSceneCoordinate_m));
  }
  if (glm::length(c.target - c.position) <= 0) t->fail("camera position and target must differ");
  if (glm::length(glm::cross(glm::normalize(c.target - c.position), c.up)) < 1e-4f)
    t->fail("camera up must not be parallel to the view direction");
}

}  // namespace sylva
