#pragma once
// The ground: [terrain] (an elevation raster or a procedural fBm/ridged terrain, meshed once with
// smooth normals, geometry/terrain.h) and [[grass]] (up to three grass types, feature-map grass
// bits 1–3 in order, each a patch of curved blades made once, geometry/grass.h, and instanced by
// [vegetation]); docs/scene_format.md.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_terrain(const Params& root, SceneBuilder& b);
void parse_grass(const Params& root, SceneBuilder& b);

}  // namespace sylva
