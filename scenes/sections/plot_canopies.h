#pragma once
// The plot sensor's scenes (docs/radiometry.md): [plot] (the measured rectangle, cyclic or not,
// view directions, sample counts, ground materials), [[leaves]] (leaf discs from a RAMI leaf file)
// and [[canopies]] (the RAMI abstract canopies, generated); docs/scene_format.md.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_plot(const Params& root, SceneBuilder& b);
void parse_leaves(const Params& root, SceneBuilder& b);
void parse_canopies(const Params& root, SceneBuilder& b);

}  // namespace sylva
