#pragma once
// What is rendered and where it goes: [render] (resolution, samples, seed, depth, bands, quantity,
// instancing, kernels), [[bands]] (user SRFs), [output] (files, preview exposure and view) and
// [sensor] (a real camera applied after the render: sensor/sensor_params.h);
// docs/scene_format.md.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_render(const Params& root, SceneBuilder& b);
void parse_bands(const Params& root, SceneBuilder& b);
void parse_output(const Params& root, SceneBuilder& b);
void parse_sensor(const Params& root, SceneBuilder& b);

}  // namespace sylva
