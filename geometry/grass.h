#pragma once
// Grass blades as curves (Weber & Penn §6: "curved lines", after Reeves & Blau's particle grass):
// one cubic Bézier ribbon per blade, oriented by per-control-point normals, tapering to the tip.
// A patch of blades is generated once per grass type and instanced over the terrain
// (geometry/placement.h), so a hectare of grass costs a few patches plus one transform per patch.

#include "core/math.h"

#include <cstdint>
#include <vector>

namespace sylva {

// Cubic Bézier ribbons: curve k has control points 4k … 4k+3, each (x, y, z, half-width), and a
// unit normal per control point; the ribbon spans ±half-width along cross(tangent, normal).
// With `round`, the curves are round tubes of radius w instead (Embree round Bézier curves: stems
// drawn as lines at range, geometry/trees/lod.h) and `normals` is empty. Ribbons are traced as
// triangle strips (tessellate_ribbons) unless `exact`: then as Embree's normal-oriented Bézier
// curves, the exact ribbon at several times the cost ([[grass]] trace = "curves").
struct CurveSet {
  std::vector<Vec4> points;
  std::vector<Vec3> normals;
  bool round = false;
  bool exact = false;

  size_t size() const { return points.size() / 4; }
};

struct GrassParams {
  float patch_size_m = 2.0f;      // the square patch's side
  float density_per_m2 = 800.0f;  // blades per square metre
  Vec2 length_m{0.2f, 0.4f};      // blade length drawn uniformly from [min, max]
  float width_m = 0.005f;         // blade width at the base (it tapers to 10 % at the tip)
  float bend = 0.4f;              // 0 = upright, 1 = the tip bent over to horizontal
};

// The ribbons of `curves` as flat strips of `segments` quads per curve, appended to `positions` and
// `quads`: curve k's quads are segments·k … segments·(k+1) − 1 counted from the first appended. A
// quad (q0, q1, q2, q3) is the two triangles (q0, q1, q3) and (q2, q3, q1), Embree's split of its
// own quads. The strip's vertices lie on the ribbon's edges, P(t) ± r(t)·normalize(cross(P'(t),
// N(t))) at t = i/segments, with P, r and N the cubic Bézier interpolants of the control points,
// half-widths and normals (Embree's normal-oriented curves). This is how the renderer hands grass to
// Embree: flat pieces traverse several times faster than its normal-oriented curves (bench/README.md,
// "Issue 11: the forest's time").
void tessellate_ribbons(const CurveSet& curves, int segments, std::vector<Vec3>& positions,
                        std::vector<glm::uvec4>& quads);

// A patch centred on the origin, blades rooted at z = 0, Z up. Blade i's draws come from
// hash_ids(seed, i): base position uniform in the square, heading uniform, lean and length varied.
CurveSet make_grass_patch(const GrassParams& params, uint64_t seed);

}  // namespace sylva
