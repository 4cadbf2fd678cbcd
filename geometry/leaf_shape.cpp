#include "geometry/leaf_shape.h"

#include "core/math.h"

#include <array>

namespace sylva {

namespace {

constexpr std::array<std::string_view, static_cast<size_t>(LeafShape::Count)> kNames = {
    "rectangle", "oval", "triangle", "oak3", "maple3", "maple5", "leaflets3"};

bool inside_ellipse(float u, float v, float cu, float cv, float ru, float rv) {
  return sqr((u - cu) / ru) + sqr((v - cv) / rv) <= 1.0f;
}

}  // namespace

bool leaf_shape_inside(LeafShape shape, float u, float v) {
  switch (shape) {
    case LeafShape::Rectangle: return true;
    case LeafShape::Oval: return inside_ellipse(u, v, 0.5f, 0.5f, 0.5f, 0.5f);
    case LeafShape::Triangle: return std::abs(u - 0.5f) <= 0.5f * (1.0f - v);
    default: return inside_ellipse(u, v, 0.5f, 0.5f, 0.5f, 0.5f);
  }
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
