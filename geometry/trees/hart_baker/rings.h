#pragma once
// Growth rings (Hart & Baker §6): slicing the stack of each year's trunk surfaces at a height gives
// the annual rings, eccentric where reaction wood (§5.1) and balance moved the growth to one side.

#include "geometry/trees/hart_baker/hart_baker.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sylva {

// The trunk's rings at `height_m`: one circle per year in which the trunk reached that height,
// innermost first, in the horizontal plane (world x, y; metres). The trunk is the chain of yearly
// segments from limb 0; in the segment holding the height (h above its base), a year's radius is
// its cone's radius there, R_y (1 − (1 − tip_ratio)·h/l_y), and its centre the year's
// reaction-wood offset times eq. 31's falloff c(h/δ) (reaction_wood_falloff, δ of eq. 25 as the
// drawn surface takes it: at least the base radius, at most the segment's length).
struct TrunkRings {
  float height_m = 0.0f;
  std::vector<int> year;  // 1-based year of growth that laid the ring down
  std::vector<Vec2> centre_m;
  std::vector<float> radius_m;

  size_t size() const { return year.size(); }
};
TrunkRings trunk_rings(const HartBakerTree& tree, const HartBakerParams& params, float height_m);

// CSV, one row per ring: year, radius_m, centre_x_m, centre_y_m, width_mean_m, width_min_m,
// width_max_m (widths around the ring; the first ring's from the pith).
std::string ring_widths_csv(const TrunkRings& rings);

// A size × size RGB image of the cross-section: light early wood, a dark band of late wood at the
// outer edge of each ring, bark outside the last ring, white around. Top row first, +y up.
std::vector<uint8_t> ring_image_rgb8(const TrunkRings& rings, int size);

}  // namespace sylva
