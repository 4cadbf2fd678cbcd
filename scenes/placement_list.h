#pragma once
// Placement lists (docs/scene_format.md [[placements]]): CSV files of trees to place, one row per
// tree, read as a stream (a line at a time, no document in memory), so a list of millions of rows
// costs its rows and nothing more.
//
// Format: `#` starts a comment line; blank lines are skipped; the first other line is the header,
// naming the columns in any order: x, y, species, seed, scale, heading (required) and z (optional,
// default 0). Fields are separated by commas, spaces around them are ignored, no quoting.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string_view>

namespace sylva {

inline constexpr uint64_t kMaxPlacementFileBytes = uint64_t{16} << 30;

// One row: position (m), species name (as the [[placements]] entry's `species` table names it),
// generator seed, uniform scale (> 0) and heading (degrees, compass bearing of the tree's +Y axis).
struct PlacementRow {
  float x = 0, y = 0, z = 0;
  std::string_view species;  // valid during the callback only
  uint64_t seed = 0;
  float scale = 1;
  float heading_deg = 0;
};

// Calls `row(r, line)` for every data row of `file` in order (line = 1-based line number). Throws
// ParseError `file:line: what was expected` for a missing column, a bad number, a scale that is not
// positive, a coordinate beyond `max_coordinate_m`, or an unreadable file; `row` may throw too.
void for_each_placement_row(const std::filesystem::path& file, float max_coordinate_m,
                            const std::function<void(const PlacementRow&, int line)>& row);

}  // namespace sylva
