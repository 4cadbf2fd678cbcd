#include "geometry/leaf_shape.h"

#include "core/math.h"

#include <array>
#include <cmath>

namespace sylva {

namespace {

constexpr std::array<std::string_view, static_cast<size_t>(LeafShape::Count)> kNames = {
    "rectangle", "oval", "triangle", "oak3", "maple3", "maple5", "leaflets3", "right_triangle"};

// An ellipse with semi-axes (ru across, rv along) whose long axis is turned by `angle_rad` from +v
// toward +u.
bool inside_rotated_ellipse(float u, float v, float cu, float cv, float ru, float rv, float cos_a, float sin_a) {
  const float du = u - cu, dv = v - cv;
  const float along = du * sin_a + dv * cos_a;
  const float across = du * cos_a - dv * sin_a;
  return sqr(across / ru) + sqr(along / rv) <= 1.0f;
}

// A palmate (maple) outline: pointed lobes radiating from (0.5, cv). The radius in direction θ
// (measured from +v, positive toward +u) rises linearly from `notch` to each lobe's length within
// `half_width` radians of the lobe's direction, which makes pointed tips and sharp sinuses.
template <size_t N>
bool inside_palmate(float u, float v, float cv, const std::array<float, N>& lobe_dir,
                    const std::array<float, N>& lobe_len, float half_width, float notch) {
  const float du = u - 0.5f, dv = v - cv;
  const float r2 = du * du + dv * dv;
  if (r2 <= notch * notch) return true;
  const float theta = std::atan2(std::abs(du), dv);  // symmetric about the midrib
  float r = notch;
  for (size_t i = 0; i < N; ++i) {
    const float t = 1.0f - std::abs(theta - lobe_dir[i]) / half_width;
    if (t > 0.0f) r = std::max(r, notch + (lobe_len[i] - notch) * t);
  }
  return r2 <= r * r;
}

// Weber & Penn §4.5 leaf outlines over the unit square (u across, v petiole → tip), symmetric
// about the midrib u = 0.5.
bool inside_oak3(float u, float v) {
  // Three rounded lobes (two lateral, one terminal) on a tapering blade, as in a blackjack oak.
  const float du = std::abs(u - 0.5f);
  if (inside_ellipse(du, v, 0.0f, 0.45f, 0.23f, 0.45f)) return true;
  if (sqr(du - 0.27f) + sqr(v - 0.6f) <= sqr(0.18f)) return true;
  return sqr(du) + sqr(v - 0.8f) <= sqr(0.2f);
}

bool inside_maple3(float u, float v) {
  static constexpr std::array<float, 3> dir = {0.0f, 1.05f, 2.3f};
  static constexpr std::array<float, 3> len = {0.56f, 0.47f, 0.26f};
  return inside_palmate(u, v, 0.4f, dir, len, 0.8f, 0.24f);
}

bool inside_maple5(float u, float v) {
  static constexpr std::array<float, 4> dir = {0.0f, 0.8f, 1.6f, 2.5f};
  static constexpr std::array<float, 4> len = {0.56f, 0.5f, 0.4f, 0.24f};
  return inside_palmate(u, v, 0.42f, dir, len, 0.5f, 0.2f);
}

bool inside_leaflets3(float u, float v) {
  // A terminal leaflet and two lateral leaflets turned 55° outward, on a short rachis.
  const float du = std::abs(u - 0.5f);
  if (du <= 0.015f && v <= 0.45f) return true;
  if (inside_ellipse(du, v, 0.0f, 0.72f, 0.14f, 0.27f)) return true;
  constexpr float c = 0.5735764f, s = 0.8191520f;  // cos, sin of 55°
  return inside_rotated_ellipse(du, v, 0.22f, 0.4f, 0.11f, 0.24f, c, s);
}

}  // namespace

bool leaf_shape_inside(LeafShape shape, float u, float v) {
  switch (shape) {
    case LeafShape::Rectangle:
      return true;
    case LeafShape::Oval:
      return inside_oval(u, v);
    case LeafShape::Triangle:
      return std::abs(u - 0.5f) <= 0.5f * (1.0f - v);
    case LeafShape::Oak3:
      return inside_oak3(u, v);
    case LeafShape::Maple3:
      return inside_maple3(u, v);
    case LeafShape::Maple5:
      return inside_maple5(u, v);
    case LeafShape::Leaflets3:
      return inside_leaflets3(u, v);
    case LeafShape::RightTriangle:
      return u + v <= 1.0f;
    case LeafShape::Count:
      break;
  }
  return false;
}

float leaf_shape_coverage(LeafShape shape) {
  // Midpoint-rule estimate on a 256² grid, computed once per shape.
  static const auto table = [] {
    std::array<float, static_cast<size_t>(LeafShape::Count)> t{};
    constexpr int n = 256;
    for (size_t s = 0; s < t.size(); ++s) {
      int count = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          count += leaf_shape_inside(static_cast<LeafShape>(s), (i + 0.5f) / n, (j + 0.5f) / n);
      t[s] = static_cast<float>(count) / (n * n);
    }
    return t;
  }();
  return table[static_cast<size_t>(shape)];
}

std::string_view leaf_shape_name(LeafShape shape) { return kNames[static_cast<size_t>(shape)]; }

std::optional<LeafShape> leaf_shape_from_name(std::string_view name) {
  for (size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return static_cast<LeafShape>(i);
  return std::nullopt;
}

}  // namespace sylva
