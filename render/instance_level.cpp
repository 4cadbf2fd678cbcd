// Which instance level a scene's copies reach Embree through (render/embree_scene.h).

#include "core/error.h"
#include "render/embree_scene.h"
#include "render/instance_sweep.h"

#include <fmt/core.h>

namespace sylva {

namespace {

// Embree instances of `scene`: a cyclic plot's nine copies of each instance counted.
size_t embree_instances(const Scene& scene) {
  return scene.instances.size() * (scene.plot.defined && scene.plot.cyclic ? 9 : 1);
}

}  // namespace

bool uses_instance_array(const Scene& scene) {
  switch (scene.instance_level) {
    case InstanceLevel::native:
    case InstanceLevel::sweep:
      return false;
    case InstanceLevel::array:
      return true;
    case InstanceLevel::automatic:
      break;
  }
  return embree_instances(scene) >= kInstanceArrayThreshold;
}

bool uses_instance_sweep(const Scene& scene) {
  switch (scene.instance_level) {
    case InstanceLevel::native:
    case InstanceLevel::array:
      return false;
    case InstanceLevel::sweep:
      if (embree_instances(scene) > InstanceBoxes::kMaxCopies)
        throw Error(
            fmt::format("instancing = \"sweep\" takes at most {} copies, not {} (a cyclic plot counts nine "
                        "of each instance): use \"auto\" or \"native\"",
                        InstanceBoxes::kMaxCopies, embree_instances(scene)));
      return true;
    case InstanceLevel::automatic:
      break;
  }
  return embree_instances(scene) <= InstanceBoxes::kMaxCopies;
}

}  // namespace sylva
