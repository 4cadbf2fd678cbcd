#include "geometry/trees/weber_penn/weber_penn.h"

#include "core/error.h"
#include "geometry/trees/weber_penn/weber_penn_builder.h"
#include "geometry/trees/weber_penn/weber_penn_frames.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace sylva {
namespace wp {

Builder::Builder(const WeberPennParams& params, uint64_t seed, TreeModel& model, Lengths lengths,
                 std::vector<float>* pruned_lengths)
    : p_(params),
      seed_(seed),
      m_(model),
      lengths_(lengths),
      pruned_(pruned_lengths),
      ground_(!params.asks_below_ground()) {
  // §4.5 leaf size: LeafScale/√quality by LeafScale·LeafScaleX/√quality.
  const float q = std::sqrt(std::max(1e-6f, p_.quality * p_.leaf_quality));
  leaf_length_ = p_.leaf_scale / q;
  leaf_width_ = p_.leaf_scale * p_.leaf_scale_x / q;
  const size_t n = static_cast<size_t>(std::max(1, p_.levels)) + 1;
  split_error_.assign(n, 0.0f);
  plans_.resize(n);
  plan_size_.assign(n, 0);
  segments_.resize(n);
  z_samples_.resize(n);
}

void Builder::build() {
  Pcg32 rng(hash_ids(seed_, 0x7EEull));
  // §4.3: scale_tree = Scale ± ScaleV; the trunk length (0Length ± 0LengthV)·scale_tree.
  scale_tree_ = std::max(1e-4f, p_.scale + p_.scale_v * rng.symmetric());
  z_scale_ = p_.z_scale + p_.z_scale_v * rng.symmetric();
  length_base_ = p_.base_size * scale_tree_;
  // 0Branches trunks (as Arbaro builds them, TreeImpl.make): each turned about the vertical by
  // 0Rotate ± 0RotateV from the previous one (alternating when negative), tilted by
  // 0DownAngle ± 0DownAngleV, and set off its base by ±0BranchDist metres in a random direction.
  // The first trunk draws from the tree's stream, so a one-trunk tree is unchanged by the others.
  const WeberPennLevel& l0 = p_.at(0);
  const Frame upright{};
  Pcg32 placement(hash_ids(seed_, 0x7C2ull));
  float rotate_deg = 0.0f;
  int alternate = 1;
  for (int k = 0; k < std::max(1, l0.branches); ++k) {
    Pcg32 trunk_rng = k == 0 ? rng : Pcg32(hash_ids(seed_, 0x7EEull, static_cast<uint64_t>(k)));
    const float length = std::max(0.0f, (l0.length + l0.length_v * trunk_rng.symmetric()) * scale_tree_);
    // §4.4: radius_trunk = length_trunk·Ratio·(0Scale ± 0ScaleV) (docs/design.md §5.1).
    const float trunk_scale = p_.trunk_scale + p_.trunk_scale_v * trunk_rng.symmetric();
    const float u_down = placement.symmetric();
    const float u_rot = placement.symmetric();
    const float heading = placement.uniform() * kTwoPi;
    const float dist = l0.branch_dist * placement.symmetric();
    if (length < kMinStemLength) continue;

    StemState t;
    t.level = 0;
    t.seed = k == 0 ? hash_ids(seed_, 0x7C0ull) : hash_ids(seed_, 0x7C0ull, static_cast<uint64_t>(k));
    t.rng = Pcg32(t.seed);
    t.length = length;
    t.base_radius = length * p_.ratio * trunk_scale;
    t.length_child_max = l0.length;
    t.pos = Vec3(dist * std::cos(heading), dist * std::sin(heading), 0.0f);
    t.section_frame = t.frame =
        orient_child(upright, l0, p_.reading, 1.0f, u_down, u_rot, false, 0.0f, rotate_deg, alternate);
    // A leaning trunk's base ring would dip below the ground by its radius times the lean: it
    // stands that much higher.
    if (ground_) {
      const float lean = std::sqrt(std::max(0.0f, 1.0f - t.frame.z.z * t.frame.z.z));
      t.pos.z += radius_at(t, 0.0f) * (1.0f + std::max(0.0f, p_.lobe_depth)) * lean;
    }
    init_random_state(t);
    init_counts(t);
    t.plan_node = plan_family(0);
    form(t, false);
  }
  finish();
}

// Per-stem random state drawn right after creation, in a fixed order.
void Builder::init_random_state(StemState& s) {
  s.sway_offset_x = s.rng.uniform() * kTwoPi;
  s.sway_offset_y = s.rng.uniform() * kTwoPi;
  s.rotate_deg = s.rng.uniform() * 360.0f;
  s.leaf_rotate_deg = s.rng.uniform() * 360.0f;
  s.child_carry = s.rng.uniform();
  s.leaf_carry = s.rng.uniform();
  s.helix_frame = s.frame;
}

// §4.3 child counts and §4.5 leaf counts, per segment (the trunk: per metre above BaseSize).
void Builder::init_counts(StemState& s) const {
  const int n = std::max(1, p_.at(s.level).curve_res);
  const int next = s.level + 1;
  if (next < p_.levels) {
    const int branches = p_.at(next).branches;
    float count = 0.0f;
    if (s.level == 0) {
      const float span = s.length - length_base_;
      count = span > 0.0f ? static_cast<float>(branches) / span : 0.0f;
      s.children_per_segment = count;
    } else {
      if (s.level == 1)
        count = child_count_level1(branches, s.length, s.parent_length, s.length_child_max);
      else
        count = child_count_deeper(branches, s.offset, s.parent_length);
      // Arbaro counts whole stems per stem (truncated; the guard keeps 29.99999 from becoming 29).
      if (p_.reading == Reading::Arbaro) count = std::floor(count + 1e-4f);
      s.children_per_segment = std::max(0.0f, count) / static_cast<float>(n);
    }
  }
  if (s.level == p_.levels - 1 && p_.leaves > 0) {
    const float q = p_.quality * p_.leaf_quality;
    const float count =
        leaf_count(p_.leaves, p_.leaf_distrib, s.offset, s.level == 0 ? 0.0f : s.parent_length, q, p_.reading);
    s.leaves_per_segment = std::max(0.0f, count) / static_cast<float>(n);
  }
}

// Extra cross-sections inside segments where the radius is not linear in Z: the flared trunk
// base, rounded ends (nTaper in (1, 3)) and periodic tapering (nTaper in (2, 3)).
void Builder::make_z_samples(const StemState& s, std::vector<float>& zs) const {
  zs.clear();
  const float taper = p_.at(s.level).taper;
  if (s.level == 0 && p_.flare != 0.0f) zs.insert(zs.end(), std::begin(kFlareZ), std::end(kFlareZ));
  if (taper > 1.0f && s.length > 0.0f) {
    const float unit_taper = taper < 2.0f ? 2.0f - taper : 0.0f;
    const float tip_r = std::max(s.base_radius * (1.0f - unit_taper), 1e-6f);
    if (taper > 2.0f) {
      const float spacing = 2.0f * s.base_radius / 8.0f;
      const int count = std::min(512, static_cast<int>(s.length / std::max(spacing, 1e-6f)));
      for (int k = 1; k < count; ++k) zs.push_back(static_cast<float>(k) * spacing / s.length);
    }
    for (int k = 0; k < kTipRings; ++k) {
      const float z2 = tip_r * (1.0f - std::cos(static_cast<float>(k + 1) * 0.5f * kPi / kTipRings));
      zs.push_back(1.0f - std::min(z2, tip_r) / s.length);
    }
  }
  std::sort(zs.begin(), zs.end());
}

// Appends stem s to the model (its first cross-section at unit position z_begin) and returns its
// index; the segments' sections follow as they are formed.
int Builder::begin_stem(const StemState& s, float z_begin) {
  segments_[static_cast<size_t>(s.level)].clear();
  const int stem_index = static_cast<int>(m_.stems.size());
  if (m_.stems.size() >= kMaxStems)
    throw Error("tree too large: more than " + std::to_string(kMaxStems) +
                " stems (lower nBranches, Levels or the quality factor)");
  TreeStems& st = m_.stems;
  st.level.push_back(static_cast<uint8_t>(s.level));
  st.parent.push_back(s.parent);
  st.clone_of.push_back(s.clone_of);
  st.first_section.push_back(static_cast<uint32_t>(m_.sections.size()));
  st.section_count.push_back(0);
  st.length_m.push_back(s.length);
  st.base_radius_m.push_back(s.base_radius);
  st.offset_m.push_back(s.offset);
  st.lobes.push_back(static_cast<uint8_t>(s.level == 0 ? std::clamp(p_.lobes, 0, 255) : 0));
  st.lobe_depth.push_back(s.level == 0 ? p_.lobe_depth : 0.0f);
  emit(s.pos, s.section_frame, radius_at(s, z_begin), z_begin * s.length);
  return stem_index;
}

// The frame of segment i of n (length seg_len, starting at pos) from the previous segment's f:
// curvature (§4.1), vertical attraction (§4.8) and wind sway (§4.7), kept above the ground.
Frame Builder::turn_segment(StemState& s, Frame f, const Vec3& pos, int i, int n, float seg_len) const {
  const WeberPennLevel& lp = p_.at(s.level);
  const float z0 = static_cast<float>(i) / static_cast<float>(n);
  const float z1 = static_cast<float>(i + 1) / static_cast<float>(n);
  // §4.1 curvature.
  if (lp.curve_v < 0.0f) {
    // Helix: the segments precess once about the stem's initial axis, tilted by |nCurveV|.
    const float turn = kTwoPi * (static_cast<float>(i) + 0.5f) / static_cast<float>(n);
    f = rotate_x(rotate_z(s.helix_frame, turn), radians(-lp.curve_v));
  } else if (i > 0) {
    // Every segment turns away from the previous one; the first keeps the direction the down
    // and rotate angles gave the stem (both readings, docs/weber_penn.md).
    float curve = segment_curve_deg(lp.curve, lp.curve_back, n, i) + s.split_correction_deg;
    // "A random rotation of magnitude nCurveV/nCurveRes is also added": a magnitude, its axis
    // random across the stem, in both readings (as Arbaro's newDirection; docs/weber_penn.md).
    const float random_deg = lp.curve_v / static_cast<float>(n) * s.rng.symmetric();
    f = rotate_x(f, radians(curve));
    const float about = s.rng.uniform() * kTwoPi;
    f = rotate_axis(f, f.x * std::cos(about) + f.y * std::sin(about), radians(random_deg));
  }
  // §4.8 vertical attraction, levels ≥ 2, about the horizontal axis across the stem.
  if (i > 0 && s.level >= 2 && p_.attraction_up != 0.0f) f = turn_up(f, attraction_up_rad(p_.attraction_up, f.z.z, n));
  // §4.7 wind sway about the segment's x and y axes.
  if (p_.wind.active()) {
    const Sway sway = sway_angles(s.length, s.base_radius, radius_at(s, z0), z0, n, p_.wind.speed, p_.wind.gust,
                                  p_.wind.time_s, p_.wind.time_scale, s.sway_offset_x, s.sway_offset_y);
    f = rotate_y(rotate_x(f, radians(sway.x_deg)), radians(sway.y_deg));
  }
  f = orthonormalized(f);
  // The clearance is the segment's larger end radius: the rings of a rounded tip (nTaper > 1)
  // inside the last segment are wider than its end.
  if (ground_) f = keep_above_ground(f, pos, seg_len, std::max(radius_at(s, z0), radius_at(s, z1)));
  return f;
}

// Forms segments [s.segment, nCurveRes) of stem s (§4.1–4.2). Probe: only tests the points
// against the pruning envelope, including every clone's, and returns the index of the first
// segment reaching outside (−1 when all inside). Otherwise: appends the stem, spawns its
// children and leaves (§4.3, §4.5), then forms its clones.
int Builder::form(StemState s, bool probe) {
  const WeberPennLevel& lp = p_.at(s.level);
  const int n = std::max(1, lp.curve_res);
  const float seg_len = s.length / static_cast<float>(n);
  std::vector<float>& zs = z_samples_[static_cast<size_t>(s.level)];
  make_z_samples(s, zs);
  size_t zi = 0;
  const float z_begin = static_cast<float>(s.segment) / static_cast<float>(n);
  while (zi < zs.size() && zs[zi] <= z_begin + 1e-6f) ++zi;

  std::vector<SegmentStart>& segs = segments_[static_cast<size_t>(s.level)];
  const int stem_index = probe ? -1 : begin_stem(s, z_begin);

  // A probe forms the stem's clones too, which the real pass will append: once they outnumber the
  // stems still allowed, the tree is too large (without this, splitting clones hang the probe).
  if (probe) {
    if (probe_budget_ == 0)
      throw Error("tree too large: more than " + std::to_string(kMaxStems) +
                  " stems (lower nBranches, nSegSplits, Levels or the quality factor)");
    --probe_budget_;
  }

  std::vector<StemState> clones;
  size_t clone_cursor = 0;  // the next of this stem's clones in the plan
  int first_out = -1;
  Frame f = s.frame;
  Vec3 pos = s.pos;
  for (int i = s.segment; i < n; ++i) {
    const float z0 = static_cast<float>(i) / static_cast<float>(n);
    const float z1 = static_cast<float>(i + 1) / static_cast<float>(n);
    f = turn_segment(s, f, pos, i, n, seg_len);

    if (!probe) segs.push_back({pos, f, i, s.children_per_segment, s.leaves_per_segment});
    for (; zi < zs.size() && zs[zi] < z1 - 1e-6f; ++zi) {
      const Vec3 q = pos + f.z * ((zs[zi] - z0) * s.length);
      if (probe) {
        if (first_out < 0 && !inside(q)) first_out = i;
      } else {
        emit(q, f, radius_at(s, zs[zi]), zs[zi] * s.length);
      }
    }
    const Vec3 end = pos + f.z * seg_len;
    if (probe) {
      if (first_out < 0 && !inside(end)) first_out = i;
    } else {
      emit(end, f, radius_at(s, z1), z1 * s.length);
    }

    // §4.2 splits at the end of every segment but the last, as planned for the family.
    if (i < n - 1 && s.plan_node >= 0) {
      const SplitNode& node = plans_[static_cast<size_t>(s.level)][static_cast<size_t>(s.plan_node)];
      const int splits = node.splits[static_cast<size_t>(i - node.first_segment)];
      if (splits > 0) split(s, f, end, i, n, splits, stem_index, clones, clone_cursor);
    }
    pos = end;
  }

  if (probe) {
    for (StemState& c : clones) {
      const int out = form(c, true);
      if (out >= 0 && (first_out < 0 || out < first_out)) first_out = out;
    }
    return first_out;
  }

  m_.stems.section_count[static_cast<size_t>(stem_index)] =
      static_cast<uint32_t>(m_.sections.size()) - m_.stems.first_section[static_cast<size_t>(stem_index)];
  spawn_children(s, stem_index, seg_len, pos, f);
  for (StemState& c : clones) form(c, false);
  return -1;
}

// §4.2: the stem and its `splits` clones each turn away by angle_split about x, then spread
// about the vertical axis through the split point; the deflection is later corrected over the
// remaining segments. One clone: the two turn to opposite sides by half of the paper's spread
// angle each, so they diverge by the "20 to 50 degrees" §4.2 describes for horizontal stems;
// k clones: 360/(k+1) degrees apart (docs/design.md §5.1). `f` is the stem's frame, updated in place.
void Builder::split(StemState& s, Frame& f, const Vec3& at, int i, int n, int splits, int stem_index,
                    std::vector<StemState>& clones, size_t& clone_cursor) {
  const WeberPennLevel& lp = p_.at(s.level);
  const float declination = degrees(safe_acos(f.z.z));
  const float angle = split_angle_deg(lp.split_angle, lp.split_angle_v, s.rng.symmetric(), declination);
  const float remaining = static_cast<float>(n - 1 - i);
  const float correction = remaining > 0.0f ? -angle / remaining : 0.0f;
  float spread = 0.0f;
  if (splits == 1) {
    const float sign = s.rng.uniform() < 0.5f ? -1.0f : 1.0f;
    spread = 0.5f * sign * split_spread_deg(declination, s.rng.uniform());
  }
  // The stem and its clones share the children the stem would have carried over its remaining
  // segments (as Arbaro does). The paper reading shares the leaves too (docs/weber_penn.md,
  // "Readings"); Arbaro gives every clone the full leaf count.
  const float share = 1.0f / static_cast<float>(splits + 1);
  s.children_per_segment *= share;
  if (p_.reading == Reading::Paper) s.leaves_per_segment *= share;
  const SplitNode& node = plans_[static_cast<size_t>(s.level)][static_cast<size_t>(s.plan_node)];
  const Frame pre = f;
  const Vec3 up{0.0f, 0.0f, 1.0f};
  for (int c = 0; c <= splits; ++c) {
    const float about_z =
        splits == 1 ? (c == 0 ? spread : -spread) : 360.0f * static_cast<float>(c) / static_cast<float>(splits + 1);
    const Frame g = orthonormalized(rotate_axis(rotate_x(pre, radians(angle)), up, radians(about_z)));
    if (c == 0) {
      f = g;
      continue;
    }
    StemState k = s;
    k.clone_of = stem_index;
    k.seed = hash_ids(s.seed, 0xC10ull, static_cast<uint64_t>(i), static_cast<uint64_t>(c));
    k.rng = Pcg32(k.seed);
    k.pos = at;
    k.section_frame = pre;
    k.frame = g;
    k.segment = i + 1;
    k.split_correction_deg = correction;
    k.plan_node = node.clones[clone_cursor++];
    k.child_counter = 0;
    init_random_state(k);
    k.helix_frame = s.helix_frame;
    clones.push_back(k);
  }
  s.split_correction_deg = correction;
}

// §4.2 splits of a stem and all its clones (a family), decided in Arbaro's order (makeClones): the
// stem decides segment by segment, and each clone, made at once, decides all of its own before
// the stem goes on; the level's error value runs through the decisions in that order. Sylva forms
// a stem's segments before its clones, so the decisions are made first and read back (the order
// matters: with 1SegSplits = 0.25 over 17 segments a family has 24 stems one way, 28 the other).
// Pruning probes read the plan without using up error. Returns the root's entry, or −1 when the
// level never splits.
int Builder::plan_family(int level) {
  const bool base_splits = level == 0 && p_.base_splits > 0;
  if (!base_splits && p_.at(level).seg_splits <= 0.0f) return -1;
  plan_size_[static_cast<size_t>(level)] = 0;
  return plan_stem(level, 0, base_splits, false, plans_[static_cast<size_t>(level)]);
}

int Builder::plan_stem(int level, int first_segment, bool base_splits, bool halved, std::vector<SplitNode>& plan) {
  const WeberPennLevel& lp = p_.at(level);
  const int n = std::max(1, lp.curve_res);
  size_t& size = plan_size_[static_cast<size_t>(level)];
  const int id = static_cast<int>(size);
  if (size >= kMaxStems)
    throw Error("tree too large: more than " + std::to_string(kMaxStems) +
                " stems (lower nSegSplits, 0BaseSplits or nCurveRes)");
  if (size == plan.size()) plan.emplace_back();  // entries are reused from family to family
  ++size;
  plan[static_cast<size_t>(id)].first_segment = first_segment;
  plan[static_cast<size_t>(id)].splits.clear();
  plan[static_cast<size_t>(id)].clones.clear();
  for (int i = first_segment; i < n - 1; ++i) {
    int splits = 0;
    if (base_splits && i == 0) {
      splits = p_.base_splits;
    } else if (lp.seg_splits > 0.0f) {
      splits = diffuse_splits(lp.seg_splits * (halved ? 0.5f : 1.0f), split_error_[static_cast<size_t>(level)]);
    }
    plan[static_cast<size_t>(id)].splits.push_back(splits);
    if (splits == 0) continue;
    // §4.3 "any stem that has been cloned or is, itself, a clone reduces its propensity to form
    // clones by half": the paper reading; Arbaro never halves.
    halved = p_.reading == Reading::Paper;
    for (int c = 0; c < splits; ++c) {
      const int clone = plan_stem(level, i + 1, false, halved, plan);
      plan[static_cast<size_t>(id)].clones.push_back(clone);
    }
  }
  return id;
}

}  // namespace wp

TreeModel make_weber_penn_tree(const WeberPennParams& params, uint64_t seed) {
  TreeModel model;
  if (params.wind.active() && params.prune_ratio > 0.0f) {
    // Prune the windless tree and reuse its stem lengths, so that the wind moves the stems
    // without changing the tree's structure (docs/design.md §5.1: same seed ⇒ same tree).
    WeberPennParams calm = params;
    calm.wind = {};
    std::vector<float> lengths;
    TreeModel scratch;
    wp::Builder(calm, seed, scratch, wp::Builder::Lengths::Record, &lengths).build();
    wp::Builder(params, seed, model, wp::Builder::Lengths::Replay, &lengths).build();
    return model;
  }
  wp::Builder(params, seed, model, wp::Builder::Lengths::Probe, nullptr).build();
  return model;
}

TreeModel make_tree(const WeberPennParams& params, uint64_t seed, const TreeOptions& options) {
  WeberPennParams p = params;
  p.quality = options.quality;
  p.wind.speed = options.wind_speed;
  p.wind.gust = options.wind_gust;
  p.wind.time_s = options.time_s;
  return make_weber_penn_tree(p, seed);
}

}  // namespace sylva
