#pragma once
// A ray's walk through a cyclic plot's cell (PlotDesc::cyclic, EmbreeScene): the ray traced inside
// the plot's cell only, its segments clipped at the cell's side walls and continued from the
// opposite wall. Inline: every ray of a cyclic plot takes these steps.

#include "core/math.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sylva {

// A ray in a cyclic plot that crosses this many cell walls without hitting anything is taken to
// escape: only rays within a few degrees of horizontal in an empty layer get this far.
inline constexpr int kMaxCellCrossings = 4096;

// `x` wrapped into [lo, lo + period).
inline float wrap_into_cell(float x, float lo, float period) {
  float w = x - period * std::floor((x - lo) / period);
  if (w >= lo + period) w -= period;
  return w;
}

// A ray's walk through a cyclic plot's cell: the current origin (wrapped into the cell), the
// distance travelled so far, and the length of the segment inside the cell.
struct CellWalk {
  Vec3 origin;
  float travelled = 0;
  float segment = 0;   // to the next side wall; infinity for a vertical ray
  int exit_axis = -1;  // 0 = x, 1 = y wall at the segment's end
};

// Sets up the segment from walk.origin to the cell's side walls.
inline void next_segment(CellWalk& walk, const Vec3& d, Vec2 lo, Vec2 hi) {
  walk.segment = std::numeric_limits<float>::infinity();
  walk.exit_axis = -1;
  for (int a = 0; a < 2; ++a) {
    if (d[a] == 0.0f) continue;
    const float t = ((d[a] > 0 ? hi[a] : lo[a]) - walk.origin[a]) / d[a];
    if (t < walk.segment) {
      walk.segment = std::max(t, 0.0f);
      walk.exit_axis = a;
    }
  }
}

// Moves the walk to the opposite wall at the end of its segment. False when the ray has left the
// heights where geometry lies (or crossed too many walls): it escapes.
inline bool cross_wall(CellWalk& walk, const Vec3& d, Vec2 lo, Vec2 hi, float z_lo, float z_hi, int& crossings) {
  walk.origin += walk.segment * d;
  walk.travelled += walk.segment;
  const int a = walk.exit_axis;
  walk.origin[a] = d[a] > 0 ? lo[a] : hi[a];
  const int b = 1 - a;
  walk.origin[b] = std::clamp(walk.origin[b], lo[b], hi[b]);
  if ((walk.origin.z > z_hi && d.z >= 0) || (walk.origin.z < z_lo && d.z <= 0)) return false;
  return ++crossings < kMaxCellCrossings;
}

// Starts a walk through a cyclic plot's cell: from the top (or bottom) of the geometry's heights
// when the ray begins outside them, the origin wrapped into the cell. False when the ray never
// reaches those heights.
inline bool start_walk(float z_lo, float z_hi, Vec2 lo, Vec2 period, const Vec3& origin, const Vec3& d,
                       CellWalk& walk) {
  walk.origin = origin;
  if (walk.origin.z > z_hi || walk.origin.z < z_lo) {
    const float z = walk.origin.z > z_hi ? z_hi : z_lo;
    if (d.z == 0.0f || (z - walk.origin.z) / d.z < 0) return false;
    walk.travelled = (z - walk.origin.z) / d.z;
    walk.origin += walk.travelled * d;
    walk.origin.z = z;
  }
  walk.origin.x = wrap_into_cell(walk.origin.x, lo.x, period.x);
  walk.origin.y = wrap_into_cell(walk.origin.y, lo.y, period.y);
  return true;
}

}  // namespace sylva
