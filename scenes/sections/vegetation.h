#pragma once
// [vegetation]: trees and grass over the terrain from a 16-bit feature map (Weber & Penn §6,
// plates 3–4): [[vegetation.species]] name a species file per bit 0–13 with a density, minimum
// spacing, variants (seeds) and scale range; the top two bits choose a [[grass]] type. Every
// variant is generated once, in parallel (scenes/sections/tree_variant_cache.h), and instanced;
// each placed tree gets its own object id; docs/scene_format.md.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_vegetation(const Params& root, SceneBuilder& b);

}  // namespace sylva
