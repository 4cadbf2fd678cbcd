#pragma once
// Leaf outlines as alpha masks over the leaf quad's unit square (Weber & Penn §4.5, LeafShape).
// (u, v) in [0,1]^2: u across the blade (0.5 = midrib), v from petiole (0) to tip (1).

#include <cstdint>
#include <optional>
#include <string_view>

namespace sylva {

enum class LeafShape : uint8_t {
  Rectangle = 0,  // no cut-out: the whole quad (used for tests and far-field cards)
  Oval,           // Weber & Penn LeafShape 0: an ellipse filling the quad
  Triangle,
  Oak3,       // 3-lobe oak
  Maple3,     // 3-lobe maple
  Maple5,     // 5-lobe maple
  Leaflets3,  // 3 leaflets
  // The right triangle (0,0), (1,0), (0,1): u + v ≤ 1, the right angle at the petiole corner. Any
  // triangle is two of these (split at the foot of its longest edge's altitude), which is how
  // TREE-MAKER's tri= elements become leaf quads (docs/treemaker.md).
  RightTriangle,
  Count
};

// True where the leaf is opaque. Pure, branch-light: it runs inside Embree's filter callbacks.
bool leaf_shape_inside(LeafShape shape, float u, float v);

// Whether (u, v) lies in the axis-aligned ellipse of centre (cu, cv) and semi-axes (ru, rv).
inline bool inside_ellipse(float u, float v, float cu, float cv, float ru, float rv) {
  const float du = (u - cu) / ru, dv = (v - cv) / rv;
  return du * du + dv * dv <= 1.0f;
}

// LeafShape::Oval's test, inline for the leaf filter of geometry whose leaves are all oval (Weber &
// Penn's default): the ellipse inscribed in the unit square.
inline bool inside_oval(float u, float v) { return inside_ellipse(u, v, 0.5f, 0.5f, 0.5f, 0.5f); }

// Fraction of the unit square covered by the outline (the leaf's area / quad area).
float leaf_shape_coverage(LeafShape shape);

std::string_view leaf_shape_name(LeafShape shape);
std::optional<LeafShape> leaf_shape_from_name(std::string_view name);

}  // namespace sylva
