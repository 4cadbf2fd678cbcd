#include "geometry/trees/hart_baker/rings.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace sylva {

TrunkRings trunk_rings(const HartBakerTree& tree, const HartBakerParams& params, float height_m) {
  TrunkRings rings;
  rings.height_m = height_m;
  if (tree.size() == 0) return rings;
  // The trunk is the chain of yearly segments from limb 0 through each one's continuation; find
  // the segment whose span holds the height.
  size_t i = 0;
  while (tree.base[i].z + tree.length_m[i] <= height_m && tree.apex[i] >= 0 &&
         tree.alive[static_cast<size_t>(tree.apex[i])])
    i = static_cast<size_t>(tree.apex[i]);
  const float h = height_m - tree.base[i].z;
  if (h < 0.0f) return rings;
  // Each year's reaction-wood shift fades along the segment as eq. 31's c(s/δ), δ of eq. 25 as the
  // drawn surface has it (hart_baker_tree_model): at least the base radius, at most the length.
  const float reach = static_cast<float>(reaction_wood_reach(tree, params, compute_limb_sums(tree, params, {}))[i]);
  const std::vector<float>& radius = tree.ring_radius_m[i];
  for (size_t y = 0; y < radius.size(); ++y) {
    const float l = tree.ring_length_m[i][y];
    if (l <= h) continue;
    const float along = h / l;
    const float delta = std::clamp(reach, std::min(radius[y], l), l);
    const Vec3 offset = tree.ring_offset_m[i][y] * static_cast<float>(reaction_wood_falloff(h / delta));
    rings.year.push_back(static_cast<int>(y) + 1 + tree.born[i]);
    rings.centre_m.push_back(Vec2(offset.x, offset.y));
    rings.radius_m.push_back(radius[y] * (1.0f - (1.0f - params.tip_ratio) * along));
  }
  return rings;
}

std::string ring_widths_csv(const TrunkRings& rings) {
  std::string csv = "year,radius_m,centre_x_m,centre_y_m,width_mean_m,width_min_m,width_max_m\n";
  for (size_t k = 0; k < rings.size(); ++k) {
    const float inner = k > 0 ? rings.radius_m[k - 1] : 0.0f;
    const Vec2 shift = k > 0 ? rings.centre_m[k] - rings.centre_m[k - 1] : Vec2(0.0f);
    const float mean = rings.radius_m[k] - inner;
    const float s = k > 0 ? glm::length(shift) : 0.0f;
    csv += fmt::format("{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", rings.year[k], rings.radius_m[k],
                       rings.centre_m[k].x, rings.centre_m[k].y, mean, mean - s, mean + s);
  }
  return csv;
}

std::vector<uint8_t> ring_image_rgb8(const TrunkRings& rings, int size) {
  std::vector<uint8_t> rgb(static_cast<size_t>(size) * static_cast<size_t>(size) * 3, 255);
  if (rings.size() == 0) return rgb;
  const size_t last = rings.size() - 1;
  const float bark = 0.08f * rings.radius_m[last] + 1e-4f;
  const float half = 1.15f * (rings.radius_m[last] + bark + glm::length(rings.centre_m[last]));
  const float pixel = 2.0f * half / static_cast<float>(size);
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      const Vec2 p(-half + (static_cast<float>(px) + 0.5f) * pixel, half - (static_cast<float>(py) + 0.5f) * pixel);
      Vec3 c(1.0f);
      size_t ring = rings.size();
      for (size_t k = 0; k < rings.size(); ++k)
        if (glm::length(p - rings.centre_m[k]) <= rings.radius_m[k]) {
          ring = k;
          break;
        }
      if (ring < rings.size()) {
        const float inner = ring > 0 ? rings.radius_m[ring - 1] : 0.0f;
        const float width = std::max(rings.radius_m[ring] - inner, 1e-6f);
        const float to_edge = (rings.radius_m[ring] - glm::length(p - rings.centre_m[ring])) / width;
        c = to_edge < 0.22f ? Vec3(0.62f, 0.42f, 0.24f) : Vec3(0.93f, 0.80f, 0.60f);  // late / early wood
        if (ring == 0 && glm::length(p - rings.centre_m[0]) < 0.25f * rings.radius_m[0]) c = Vec3(0.55f, 0.38f, 0.22f);
      } else if (glm::length(p - rings.centre_m[last]) <= rings.radius_m[last] + bark) {
        c = Vec3(0.35f, 0.27f, 0.22f);  // bark
      }
      const size_t k = (static_cast<size_t>(py) * static_cast<size_t>(size) + static_cast<size_t>(px)) * 3;
      for (int ch = 0; ch < 3; ++ch)
        rgb[k + static_cast<size_t>(ch)] = static_cast<uint8_t>(std::lround(255.0f * c[ch]));
    }
  return rgb;
}

}  // namespace sylva
