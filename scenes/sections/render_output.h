#pragma once
// What is rendered and where it goes: [render] (resolution, samples, seed, depth, bands, quantity,
// instancing, kernels), [[bands]] (user SRFs) and [output] (files, preview exposure and view);
// docs/scene_format.md.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_render(const Params& root, SceneBuilder& b);
void parse_bands(const Params& root, SceneBuilder& b);
void parse_output(const Params& root, SceneBuilder& b);

}  // namespace sylva
