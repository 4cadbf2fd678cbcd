#pragma once
// The light and the air: [sun], [sky] (a registered sky model, render/lights/lights.h, that reads
// its own parameters) and [haze] (render/media/haze.h); docs/scene_format.md.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_sun(const Params& root, SceneBuilder& b);
void parse_sky(const Params& root, SceneBuilder& b);
void parse_haze(const Params& root, SceneBuilder& b);

}  // namespace sylva
