#include "geometry/trees/lod.h"

#include <algorithm>
#include <cmath>

namespace sylva {

namespace {

float clamp01(float x) { return std::clamp(x, 0.0f, 1.0f); }

Vec3 normalize_or(const Vec3& v, const Vec3& fallback) {
  const float len = glm::length(v);
  return len > 0.0f ? v / len : fallback;
}

// The level-0 shape of §5: all up to r2 = a, then mass_size·(1.5 − r2/(2a)), none from r2 = 8a/3
// (the printed trunk equation is a = 300: 1.5 − r2/600 on 300 < r2 < 800).
float ramp_with_cutoff(float r2, float a) {
  if (r2 < a) return 1.0f;
  if (r2 >= 8.0f * a / 3.0f) return 0.0f;
  return 1.5f - r2 / (2.0f * a);
}

// Table 2's stem item: levels ≥ 2 are grouped with level 2.
int stem_item(int level) { return std::min(level, kLodStemItems - 1); }

}  // namespace

// Weber & Penn §5, "Level 0 Stems" (printed) and fits to Table 2 for the rest (docs/lod.md).
LodNumbers lod_numbers(float r2) {
  const float stem = static_cast<float>(kLodStemMassSize), leaf = static_cast<float>(kLodLeafMassSize);
  LodNumbers n;
  // Level 0: polygons mass_size for r2 < 300, mass_size·(1.5 − r2/600) to 800, none beyond; lines
  // for every segment beyond r2 = 100 ("can appear as seam" closer).
  n.polygons[0] = stem * ramp_with_cutoff(r2, 300.0f);
  n.lines[0] = r2 > 100.0f ? stem : 0.0f;
  // Level 1: Table 2 draws all tubes at 60 m and none at 120 m; the step sits at their geometric
  // mean. Lines: 1.55 − 0.0575·√r2 (least squares on 120, 240, 600 m).
  n.polygons[1] = r2 < 85.0f ? stem : 0.0f;
  n.lines[1] = stem * clamp01(1.55f - 0.0575f * std::sqrt(std::max(r2, 0.0f)));
  // Level 2: the level-0 shape with a = 22.1 (through 30 m: 14580/17736; zero by 60 m). Lines:
  // 1.37 − r2/131 (through 60 and 120 m).
  n.polygons[2] = stem * ramp_with_cutoff(r2, 22.1f);
  n.lines[2] = stem * clamp01(1.37f - r2 / 131.0f);
  // Leaves: polygons 1.34 − r2/148 (through 60 and 120 m). Points 1.412 − r2/466 (through 240 and
  // 600 m), never below 1/8: Table 2 keeps 1664 of 13312 points at both 600 and 1200 m, which no
  // decreasing ramp gives, so the eighth is read as a floor (one point in every second mass).
  n.leaf_polygons = leaf * clamp01(1.34f - r2 / 148.0f);
  n.leaf_points = leaf * std::max(clamp01(1.412f - r2 / 466.0f), 0.125f);
  return n;
}

int lod_mass_drawn(size_t mass, size_t total, float number, int mass_size) {
  const size_t size = static_cast<size_t>(mass_size);
  const size_t masses = (total + size - 1) / size;
  if (mass >= masses) return 0;
  const float clamped = std::clamp(number, 0.0f, static_cast<float>(mass_size));
  const float whole = std::floor(clamped);
  // The number of masses drawing one more, rounded to the nearest (5.3f is 5.3000002: the paper's
  // 10 masses give 3, not 4), spread evenly over the masses: mass m draws one more when
  // ⌊(m + 1)·change/masses⌋ > ⌊m·change/masses⌋. The paper gives them to the first `change`
  // masses; since elements are in the order they were made (the tree's bottom first), that
  // thins the top of the tree: at 1200 m (0.5 of 4 leaves) its upper half would keep no leaf.
  const size_t change =
      static_cast<size_t>(std::llround(static_cast<double>(masses) * static_cast<double>(clamped - whole)));
  const size_t extra = (mass + 1) * change / masses - mass * change / masses;
  const size_t drawn = static_cast<size_t>(whole) + extra;
  const size_t in_mass = std::min(size, total - mass * size);
  // A last, partial mass draws its share of `number` (the paper's loop would draw up to `number`
  // of it, too many for an item of few elements: a trunk of 11 segments would keep 8 of 11, not half).
  if (in_mass < size)
    return static_cast<int>(
        std::lround(static_cast<double>(clamped) * static_cast<double>(in_mass) / static_cast<double>(size)));
  return static_cast<int>(drawn);
}

bool lod_is_drawn(size_t index, size_t total, float number, int mass_size) {
  const size_t size = static_cast<size_t>(mass_size);
  return index < total && index % size < static_cast<size_t>(lod_mass_drawn(index / size, total, number, mass_size));
}

size_t lod_drawn_count(size_t total, float number, int mass_size) {
  const size_t size = static_cast<size_t>(mass_size);
  size_t n = 0;
  for (size_t m = 0; m * size < total; ++m) n += static_cast<size_t>(lod_mass_drawn(m, total, number, mass_size));
  return n;
}

float lod_calibrated_range(float pixel_footprint_m) {
  // The reference pixel: 2·tan(30°)/1000 radians, so r2 = range for a 1000-row, 60° camera.
  const float reference = 2.0f * std::tan(radians(30.0f)) / 1000.0f;
  return pixel_footprint_m / reference;
}

int lod_level_for(float r2) {
  int level = 0;
  for (size_t k = 1; k < kLodLevelR2.size(); ++k)
    if (r2 >= kLodLevelR2[k]) level = static_cast<int>(k);
  return level;
}

double leaf_outline_area(const LeafQuads& quads) {
  double area = 0;
  for (size_t i = 0; i < quads.size(); ++i)
    area += static_cast<double>(leaf_quad_area(quads, i)) * leaf_shape_coverage(quads.shapes[i]);
  return area;
}

namespace {

// A segment's or leaf's role: a tube (or quad), a line (or disc), or skipped.
enum Role : uint8_t { kSkip = 0, kLine = 1, kTube = 2 };

// Each segment's role, per stem: of every mass the first `polygons` are tubes and the next, up to
// `lines`, are lines: an element is drawn once, by the finer primitive. Fills out's segment counts
// and its lines' radius scale.
std::vector<std::vector<uint8_t>> segment_roles(const TreeModel& model, const LodNumbers& numbers, TreeLod& out) {
  const TreeStems& stems = model.stems;
  const StemSections& sec = model.sections;
  // Segments per item, in stem order then along the stem (the order they were made).
  for (size_t s = 0; s < stems.size(); ++s)
    if (stems.section_count[s] >= 2) out.counts.segments[stem_item(stems.level[s])] += stems.section_count[s] - 1;
  std::vector<std::vector<uint8_t>> roles(stems.size());
  std::array<size_t, kLodStemItems> next{};
  std::array<double, kLodStemItems> area_all{}, area_tube{}, area_line{};
  const auto segment_area = [&](uint32_t i) {
    return 0.5 * static_cast<double>(sec.radius_m[i] + sec.radius_m[i + 1]) *
           static_cast<double>(glm::length(sec.positions[i + 1] - sec.positions[i]));
  };
  for (size_t s = 0; s < stems.size(); ++s) {
    const uint32_t count = stems.section_count[s];
    if (count < 2) continue;
    const int item = stem_item(stems.level[s]);
    const size_t total = out.counts.segments[item];
    roles[s].resize(count - 1);
    for (uint32_t j = 0; j + 1 < count; ++j) {
      const size_t g = next[item]++;
      const bool tube = lod_is_drawn(g, total, numbers.polygons[item], kLodStemMassSize);
      const bool line = lod_is_drawn(g, total, numbers.lines[item], kLodStemMassSize);
      roles[s][j] = tube ? kTube : line ? kLine : kSkip;
      const double a = segment_area(stems.first_section[s] + j);
      area_all[item] += a;
      if (tube) area_tube[item] += a;
      if (!tube && line) area_line[item] += a;
      out.counts.tube_segments[item] += tube ? 1 : 0;
      out.counts.line_segments[item] += !tube && line ? 1 : 0;
    }
  }
  // Kept lines widen so the item's projected bark area stays that of the full item.
  for (int item = 0; item < kLodStemItems; ++item)
    if (area_line[item] > 0)
      out.line_radius_scale[item] = static_cast<float>((area_all[item] - area_tube[item]) / area_line[item]);
  return roles;
}

// The tubes: every run of consecutive tube segments as a stem of its own over the same sections.
TreeModel tube_runs(const TreeModel& model, const std::vector<std::vector<uint8_t>>& roles) {
  const TreeStems& stems = model.stems;
  TreeModel runs;
  runs.sections = model.sections;
  TreeStems& rs = runs.stems;
  for (size_t s = 0; s < stems.size(); ++s) {
    const std::vector<uint8_t>& role = roles[s];
    for (size_t j = 0; j < role.size();) {
      if (role[j] != kTube) {
        ++j;
        continue;
      }
      size_t end = j;
      while (end < role.size() && role[end] == kTube) ++end;
      rs.level.push_back(stems.level[s]);
      rs.parent.push_back(-1);
      rs.clone_of.push_back(-1);
      rs.first_section.push_back(stems.first_section[s] + static_cast<uint32_t>(j));
      rs.section_count.push_back(static_cast<uint32_t>(end - j + 1));
      rs.length_m.push_back(stems.length_m[s]);
      rs.base_radius_m.push_back(stems.base_radius_m[s]);
      rs.offset_m.push_back(stems.offset_m[s]);
      rs.lobes.push_back(stems.lobes[s]);
      rs.lobe_depth.push_back(stems.lobe_depth[s]);
      if (!stems.dead.empty()) rs.dead.push_back(stems.dead[s]);
      j = end;
    }
  }
  return runs;
}

// The lines: one straight round Bézier per line segment, radius tapering along it, widened.
void add_lines(const TreeModel& model, const std::vector<std::vector<uint8_t>>& roles, const TreeMeshOptions& options,
               TreeLod& out) {
  const TreeStems& stems = model.stems;
  const StemSections& sec = model.sections;
  out.lines.round = true;
  out.dead_lines.round = true;
  for (size_t s = 0; s < stems.size(); ++s) {
    CurveSet& set = options.split_dead_stems && stems.is_dead(s) ? out.dead_lines : out.lines;
    const float widen = out.line_radius_scale[stem_item(stems.level[s])];
    for (size_t j = 0; j < roles[s].size(); ++j) {
      if (roles[s][j] != kLine) continue;
      const uint32_t i = stems.first_section[s] + static_cast<uint32_t>(j);
      const Vec3 a = sec.positions[i], b = sec.positions[i + 1];
      const float ra = sec.radius_m[i] * widen, rb = sec.radius_m[i + 1] * widen;
      for (int k = 0; k < 4; ++k) {
        const float t = static_cast<float>(k) / 3.0f;
        set.points.push_back(Vec4(a + t * (b - a), ra + t * (rb - ra)));
      }
    }
  }
}

// The leaves' roles (kTube: quad, kLine: disc) and, per material slot, how much the kept leaves
// are enlarged.
struct LeafRoles {
  std::vector<uint8_t> role;
  std::vector<float> scale;
};

// Masses of 4 in the model's order: the first `leaf_polygons` of a mass stay quads, the next, up
// to `leaf_points` (at least kLodMinLeafPoints), become discs; per material slot, the kept leaves
// are enlarged about the petiole by √(full area / kept area).
LeafRoles leaf_roles(const TreeModel& model, const LeafQuads& quads, const LodNumbers& numbers) {
  const size_t n = quads.size();
  LeafRoles out{std::vector<uint8_t>(n), {}};
  std::vector<double> slot_all, slot_kept;
  for (size_t i = 0; i < n; ++i) {
    const bool quad = lod_is_drawn(i, n, numbers.leaf_polygons, kLodLeafMassSize);
    const bool point = lod_is_drawn(i, n, std::max(numbers.leaf_points, kLodMinLeafPoints), kLodLeafMassSize);
    out.role[i] = quad ? kTube : point ? kLine : kSkip;
    const size_t slot = i < model.leaves.size() ? model.leaves.material_of(i) : uint8_t{0};
    if (slot >= slot_all.size()) {
      slot_all.resize(slot + 1, 0.0);
      slot_kept.resize(slot + 1, 0.0);
    }
    const double a = static_cast<double>(leaf_quad_area(quads, i)) * leaf_shape_coverage(quads.shapes[i]);
    slot_all[slot] += a;
    if (out.role[i] != kSkip) slot_kept[slot] += a;
  }
  out.scale.assign(slot_all.size(), 1.0f);
  for (size_t s = 0; s < out.scale.size(); ++s)
    if (slot_kept[s] > 0) out.scale[s] = static_cast<float>(std::sqrt(slot_all[s] / slot_kept[s]));
  return out;
}

// The kept leaves, enlarged: quads into out.mesh, discs into out.discs.
void add_leaves(const TreeModel& model, const LeafQuads& quads, const LodNumbers& numbers, TreeLod& out) {
  const size_t n = quads.size();
  out.counts.leaves = n;
  const LeafRoles roles = leaf_roles(model, quads, numbers);
  const std::vector<uint8_t>& role = roles.role;
  const std::vector<float>& scale = roles.scale;
  const auto slot_of = [&](size_t i) { return i < model.leaves.size() ? model.leaves.material_of(i) : uint8_t{0}; };
  if (!scale.empty()) out.leaf_scale = scale[0];
  for (size_t i = 0; i < n; ++i) {
    if (role[i] == kSkip) continue;
    const Vec3* c = &quads.corners[4 * i];
    const float k = scale[slot_of(i)];
    const Vec3 petiole = 0.5f * (c[0] + c[1]);
    if (role[i] == kTube) {
      for (int q = 0; q < 4; ++q) out.mesh.leaves.corners.push_back(petiole + k * (c[q] - petiole));
      out.mesh.leaves.shapes.push_back(quads.shapes[i]);
      if (!quads.stem.empty()) out.mesh.leaves.stem.push_back(quads.stem[i]);
      out.quad_slot.push_back(static_cast<uint8_t>(slot_of(i)));
      ++out.counts.leaf_quads;
    } else {
      const Vec3 centre = 0.25f * (c[0] + c[1] + c[2] + c[3]);
      const Vec3 normal = normalize_or(glm::cross(c[1] - c[0], c[3] - c[0]), Vec3(0, 0, 1));
      const float area = leaf_quad_area(quads, i) * leaf_shape_coverage(quads.shapes[i]);
      out.discs.add(petiole + k * (centre - petiole), k * std::sqrt(area / kPi), normal);
      out.disc_slot.push_back(static_cast<uint8_t>(slot_of(i)));
      ++out.counts.leaf_discs;
    }
  }
}

}  // namespace

TreeLod make_tree_lod(const TreeModel& model, const TreeMesh& mesh, const TreeMeshOptions& options, float r2) {
  TreeLod out;
  out.r2 = r2;
  const LodNumbers numbers = lod_numbers(r2);
  const std::vector<std::vector<uint8_t>> roles = segment_roles(model, numbers, out);
  TreeMeshOptions tube_options = options;
  tube_options.leaves = false;
  out.mesh = make_tree_mesh(tube_runs(model, roles), tube_options);
  add_lines(model, roles, options, out);
  add_leaves(model, mesh.leaves, numbers, out);
  return out;
}

}  // namespace sylva
