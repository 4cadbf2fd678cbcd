#pragma once
// [[targets]]: a mesh (OBJ/PLY) for detection studies, placed by position, heading and scale, with
// a class `label` and a material; `ground = "snap"` (default) puts its lowest point on the highest
// ground (the [[meshes]] and terrain placed so far) under its footprint's centre and corners
// (geometry/ground.h). Each target gets an object id of its own and a row in the sidecar's target
// list (SceneFile::targets); docs/scene_format.md.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_targets(const Params& root, SceneBuilder& b);

}  // namespace sylva
