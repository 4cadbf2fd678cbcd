#pragma once
// [[placements]]: trees from a placement list (a CSV `file`, scenes/placement_list.h, or TOML
// `rows`), each row x, y, species, seed, scale, heading and optional z. `species` maps the rows'
// species names to species files and their materials. Every distinct (species, seed) is a tree
// variant (scenes/sections/tree_variant_cache.h), generated once, in parallel, and added in the
// order first listed; each row is one instance per prototype of its variant, at its level of
// detail under [lod], with an object id of its own; docs/scene_format.md.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_placements(const Params& root, SceneBuilder& b);

}  // namespace sylva
