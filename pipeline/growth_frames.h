#pragma once
// `sylva grow --frames DIR`: a small path-traced preview of each kept year of a Hart–Baker tree
// (docs/hart_baker.md, "Time-lapse"), all framed on the last state's bounds so the frames do not
// jump: DIR/year_NNN.png, each written atomically.

#include "geometry/trees/hart_baker/hart_baker.h"

#include <filesystem>
#include <vector>

namespace sylva {

void write_growth_frames(const std::filesystem::path& dir, const std::vector<HartBakerTree>& states,
                         const HartBakerParams& params);

}  // namespace sylva
