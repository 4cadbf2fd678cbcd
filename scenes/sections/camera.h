#pragma once
// [camera]: the view frame and a projection from the registry (render/sensors/camera.h) that reads
// its own parameters; docs/scene_format.md.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_camera(const Params& root, SceneBuilder& b);

}  // namespace sylva
