#pragma once
// The images `sylva grow` writes beside the tree's own files: the trunk's rings and a time-lapse.

#include "geometry/trees/hart_baker/hart_baker.h"

#include <filesystem>
#include <vector>

namespace sylva {

// `sylva grow --rings H PNG`: the trunk's cross-section at height H (docs/hart_baker.md, "Rings")
// as a 512×512 PNG, and its ring widths as PNG's name with .csv; each written atomically.
// Throws when the trunk does not reach H.
void write_trunk_rings(const std::filesystem::path& png, const HartBakerTree& tree, const HartBakerParams& params,
                       float height_m);

// `--frames DIR`: a small path-traced preview of each kept year of a Hart–Baker tree
// (docs/hart_baker.md, "Time-lapse"), all framed on the last state's bounds so the frames do not
// jump: DIR/year_NNN.png, each written atomically.
void write_growth_frames(const std::filesystem::path& dir, const std::vector<HartBakerTree>& states,
                         const HartBakerParams& params);

}  // namespace sylva
