#include "compare/regions.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

namespace sylva {

const char* region_kind_name(RegionKind kind) {
  switch (kind) {
    case RegionKind::Image:
      return "image";
    case RegionKind::Tile:
      return "tile";
    case RegionKind::Grid:
      return "grid";
    case RegionKind::Class:
      return "class";
    case RegionKind::Object:
      return "object";
    case RegionKind::Sky:
      return "sky";
    case RegionKind::Material:
      return "material";
  }
  return "?";
}

std::string region_name(const RegionTest& r) {
  switch (r.kind) {
    case RegionKind::Image:
    case RegionKind::Sky:
      return region_kind_name(r.kind);
    case RegionKind::Tile:
    case RegionKind::Grid:
      return fmt::format("{} ({},{})", region_kind_name(r.kind), r.x0, r.y0);
    case RegionKind::Class:
    case RegionKind::Object:
    case RegionKind::Material:
      return fmt::format("{} {}", region_kind_name(r.kind), r.label);
  }
  return "?";
}

namespace {

using Partition = RegionMaps::Partition;

// Fills the per-region pixel counts and boxes from of_pixel.
void measure(Partition& part, int width) {
  const size_t n = part.labels.size();
  part.pixels.assign(n, 0);
  part.boxes.assign(n, {std::numeric_limits<int>::max(), std::numeric_limits<int>::max(), 0, 0});
  for (size_t p = 0; p < part.of_pixel.size(); ++p) {
    const int32_t r = part.of_pixel[p];
    if (r < 0) continue;
    const int x = static_cast<int>(p % static_cast<size_t>(width)),
              y = static_cast<int>(p / static_cast<size_t>(width));
    auto& b = part.boxes[static_cast<size_t>(r)];
    b = {std::min(b[0], x), std::min(b[1], y), std::max(b[2], x + 1), std::max(b[3], y + 1)};
    ++part.pixels[static_cast<size_t>(r)];
  }
}

// Square cells of `size` pixels.
Partition cells(RegionKind kind, int width, int height, int size) {
  Partition part;
  part.kind = kind;
  const int nx = (width + size - 1) / size, ny = (height + size - 1) / size;
  part.labels.resize(static_cast<size_t>(nx) * static_cast<size_t>(ny));
  std::iota(part.labels.begin(), part.labels.end(), int64_t{0});
  part.of_pixel.resize(static_cast<size_t>(width) * static_cast<size_t>(height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      part.of_pixel[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] =
          (y / size) * nx + x / size;
  measure(part, width);
  return part;
}

// One region per value of `channel` accepted by `keep` with at least min_pixels pixels (label
// `label_of(value)`), in increasing order of the value.
template <typename Keep>
Partition labelled(RegionKind kind, const Image& ref, int channel, int64_t min_pixels, Keep keep) {
  Partition part;
  part.kind = kind;
  const size_t n = static_cast<size_t>(ref.width) * static_cast<size_t>(ref.height);
  const size_t nc = ref.channels.size();
  std::map<int64_t, int64_t> count;
  for (size_t p = 0; p < n; ++p) {
    const auto v = static_cast<int64_t>(ref.pixels[p * nc + static_cast<size_t>(channel)]);
    if (keep(v)) ++count[v];
  }
  std::map<int64_t, int32_t> index;
  for (const auto& [v, c] : count)
    if (c >= min_pixels) {
      index[v] = static_cast<int32_t>(part.labels.size());
      part.labels.push_back(kind == RegionKind::Sky ? 0 : v);
    }
  part.of_pixel.assign(n, -1);
  for (size_t p = 0; p < n; ++p) {
    const auto v = static_cast<int64_t>(ref.pixels[p * nc + static_cast<size_t>(channel)]);
    if (auto it = index.find(v); it != index.end() && keep(v)) part.of_pixel[p] = it->second;
  }
  measure(part, ref.width);
  return part;
}

double upper_p(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

}  // namespace

RegionMaps make_region_maps(const Image& ref, const RegionOptions& options) {
  RegionMaps maps;
  maps.width = ref.width;
  maps.height = ref.height;
  const int longest = std::max(ref.width, ref.height);
  maps.partitions.push_back(cells(RegionKind::Image, ref.width, ref.height, longest));
  if (options.tile > 0 && options.tile < longest) {
    maps.tile = options.tile;
    maps.partitions.push_back(cells(RegionKind::Tile, ref.width, ref.height, options.tile));
  }
  if (options.grid > 1) {
    const int cell = (longest + options.grid - 1) / options.grid;
    if (maps.tile == 0 || cell >= 2 * maps.tile) {
      maps.grid_cell = cell;
      maps.partitions.push_back(cells(RegionKind::Grid, ref.width, ref.height, cell));
    }
  }
  if (options.labels) {
    const auto positive = [](int64_t v) { return v > 0; };
    if (int c = ref.find_channel("id.class"); c >= 0)
      maps.partitions.push_back(labelled(RegionKind::Class, ref, c, options.min_pixels, positive));
    if (int c = ref.find_channel("id.object"); c >= 0)
      maps.partitions.push_back(labelled(RegionKind::Object, ref, c, options.min_pixels, positive));
    if (int c = ref.find_channel("id.instance"); c >= 0)
      maps.partitions.push_back(
          labelled(RegionKind::Sky, ref, c, options.min_pixels, [](int64_t v) { return v == 0; }));
    if (int c = ref.find_channel("id.material"); c >= 0)
      maps.partitions.push_back(labelled(RegionKind::Material, ref, c, options.min_pixels, positive));
  }
  std::erase_if(maps.partitions, [](const Partition& p) { return p.labels.empty(); });
  return maps;
}

RegionSums::RegionSums(const RegionMaps& maps) : maps_(&maps) {
  for (const Partition& part : maps.partitions) sums_.emplace_back(part.labels.size());
}

void RegionSums::add(size_t pixel, double d, double variance, double ref) {
  const double z2 = variance > 0.0 ? d * d / variance : 0.0;
  for (size_t k = 0; k < sums_.size(); ++k) {
    const int32_t r = maps_->partitions[k].of_pixel[pixel];
    if (r < 0) continue;
    Sum& s = sums_[k][static_cast<size_t>(r)];
    ++s.n;
    s.d += d;
    s.var += variance;
    s.abs_ref += std::abs(ref);
    s.z2 += z2;
    s.z4 += z2 * z2;
  }
}

std::vector<RegionTest> RegionSums::finish(const std::string& channel, bool variance) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<RegionTest> out;
  for (size_t k = 0; k < sums_.size(); ++k) {
    const Partition& part = maps_->partitions[k];
    for (size_t r = 0; r < sums_[k].size(); ++r) {
      const Sum& s = sums_[k][r];
      RegionTest t;
      t.channel = channel;
      t.kind = part.kind;
      t.label = part.labels[r];
      const auto& b = part.boxes[r];
      t.x0 = b[0];
      t.y0 = b[1];
      t.x1 = b[2];
      t.y1 = b[3];
      t.pixels = part.pixels[r];
      t.tested = s.n;
      t.bias_z = s.var > 0.0 ? s.d / std::sqrt(s.var) : (s.d == 0.0 ? 0.0 : std::copysign(kInf, s.d));
      t.bias_p = std::isfinite(t.bias_z) ? std::erfc(std::abs(t.bias_z) / std::sqrt(2.0)) : 0.0;
      t.mean_shift = s.abs_ref > 0.0 ? s.d / s.abs_ref : (s.d == 0.0 ? 0.0 : std::copysign(kInf, s.d));
      if (variance && s.n >= kMinVariancePixels) {
        const double n = static_cast<double>(s.n);
        t.variance_tested = true;
        t.variance_ratio = s.z2 / n;
        const double spread = std::max(0.0, (s.z4 - s.z2 * s.z2 / n) / (n - 1.0));
        const double se = std::sqrt(spread / n);
        t.variance_z = se > 0.0 ? (t.variance_ratio - 1.0) / se : 0.0;
        t.variance_p = upper_p(t.variance_z);
      }
      out.push_back(std::move(t));
    }
  }
  return out;
}

int64_t holm(std::vector<RegionTest>& tests, double alpha) {
  struct Entry {
    double p;
    RegionTest* test;
    bool variance;
  };
  std::vector<Entry> family;
  for (RegionTest& t : tests) {
    family.push_back({t.bias_p, &t, false});
    if (t.variance_tested) family.push_back({t.variance_p, &t, true});
  }
  std::stable_sort(family.begin(), family.end(), [](const Entry& a, const Entry& b) { return a.p < b.p; });
  const auto m = static_cast<int64_t>(family.size());
  double adjusted = 0.0;
  bool rejecting = true;
  for (int64_t k = 0; k < m; ++k) {
    Entry& e = family[static_cast<size_t>(k)];
    adjusted = std::min(1.0, std::max(adjusted, static_cast<double>(m - k) * e.p));
    rejecting = rejecting && e.p <= alpha / static_cast<double>(m - k);
    (e.variance ? e.test->variance_p_holm : e.test->bias_p_holm) = adjusted;
    (e.variance ? e.test->variance_failed : e.test->bias_failed) = rejecting;
  }
  return m;
}

}  // namespace sylva
