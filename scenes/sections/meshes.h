#pragma once
// [[meshes]]: a built-in shape (each reading its own keys) or an OBJ/PLY file, with a material,
// placed by its transform, `instances` and `tile` (SceneBuilder::placements). Adding a built-in
// shape is one row of kShapes in meshes.cpp.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_meshes(const Params& root, SceneBuilder& b);

}  // namespace sylva
