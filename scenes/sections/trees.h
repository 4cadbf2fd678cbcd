#pragma once
// Generated trees placed one by one: [lod] (Weber & Penn §5 level of detail for every generated
// tree, docs/lod.md) and [[trees]] (a species file and seed, meshed once per distinct variant,
// scenes/sections/tree_variant_cache.h, and instanced like a mesh; a Fournier–Grindal species
// as its solids); docs/scene_format.md. [[placements]] and [vegetation] place the same variants
// from lists and feature maps (placements.h, vegetation.h).

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_lod(const Params& root, SceneBuilder& b);
void parse_trees(const Params& root, SceneBuilder& b);

}  // namespace sylva
