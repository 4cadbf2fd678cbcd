#include "geometry/trees/weber_penn/weber_penn.h"

#include "core/error.h"
#include "core/rng.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sylva {

namespace {

// Budgets that turn a runaway parameter set (e.g. nBranches in the hundreds of thousands on two
// levels) into a clear error instead of exhausting memory: far above any real tree (the Weeping
// Willow has 50k stems and 550k leaves).
constexpr size_t kMaxStems = 1'000'000;
constexpr size_t kMaxWeberPennLeaves = 10'000'000;

// Stems shorter or thinner than this are not formed (Arbaro's MIN_STEM_LEN and MIN_STEM_RADIUS:
// small plants such as Arbaro's rush have stems under a millimetre).
constexpr float kMinStemLength = 0.00001f;
constexpr float kMinStemRadius = 0.000001f;
// Pruning (§4.6) gives up on a stem shrunk below half a millimetre.
constexpr float kMinPrunedLength = 0.0005f;
// Rings of the trunk's flared base (flare_Z is non-trivial for Z < 1/8).
constexpr float kFlareZ[] = {0.005f, 0.012f, 0.022f, 0.035f, 0.05f, 0.07f, 0.095f, 0.125f};
// Rings of a rounded stem end (nTaper in (1, 3)).
constexpr int kTipRings = 6;

// Rotations of a frame about its own axes, right-handed, angles in radians.
Frame rotate_x(const Frame& f, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return Frame{f.x, c * f.y + s * f.z, c * f.z - s * f.y};
}
Frame rotate_y(const Frame& f, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return Frame{c * f.x - s * f.z, f.y, c * f.z + s * f.x};
}
Frame rotate_z(const Frame& f, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return Frame{c * f.x + s * f.y, c * f.y - s * f.x, f.z};
}
// Rodrigues rotation of v about the unit axis k by the angle whose cosine and sine are c and s.
Vec3 rotate_vector(const Vec3& v, const Vec3& k, float c, float s) {
  return v * c + glm::cross(k, v) * s + k * (glm::dot(k, v) * (1.0f - c));
}
Frame rotate_axis(const Frame& f, const Vec3& k, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return Frame{rotate_vector(f.x, k, c, s), rotate_vector(f.y, k, c, s), rotate_vector(f.z, k, c, s)};
}
// Rotation of a frame about the tree's vertical axis.
Frame rotate_about_vertical(const Frame& f, float a) {
  const float c = std::cos(a), s = std::sin(a);
  auto r = [&](const Vec3& v) { return Vec3(c * v.x - s * v.y, s * v.x + c * v.y, v.z); };
  return Frame{r(f.x), r(f.y), r(f.z)};
}

// §4.3 orientation of a child stem or leaf: turn about the parent's axis by nRotate (alternating
// when negative; `rotate_deg` and `alternate` carry the running state along the parent) or, for a
// fan, by `fan_deg` about the parent's y axis; then tilt down by nDownAngle at `ratio` along it.
Frame orient_child(const Frame& parent_frame, const WeberPennLevel& lp, wp::Reading reading, float ratio, float u_down,
                   float u_rot, bool fan, float fan_deg, float& rotate_deg, int& alternate) {
  const float down = wp::down_angle_deg(lp.down_angle, lp.down_angle_v, ratio, u_down, reading);
  if (fan) return rotate_x(rotate_y(parent_frame, radians(fan_deg)), radians(down));
  rotate_deg = wp::rotate_angle_deg(lp.rotate, lp.rotate_v, rotate_deg, alternate, u_rot);
  if (lp.rotate < 0.0f) alternate = -alternate;
  return rotate_x(rotate_z(parent_frame, radians(rotate_deg)), radians(down));
}
Frame orthonormalized(const Frame& f) {
  const Vec3 z = glm::normalize(f.z);
  Vec3 x = f.x - z * glm::dot(f.x, z);
  const float lx = glm::length(x);
  if (lx < 1e-6f) return Frame::from_z(z);
  x /= lx;
  return Frame{x, glm::cross(z, x), z};
}

// Turns frame f so that its z axis becomes `to` (unit), by the shortest rotation.
Frame turn_to(const Frame& f, const Vec3& to) {
  const Vec3 axis = glm::cross(f.z, to);
  const float s = glm::length(axis);
  if (s < 1e-7f) return f;
  return orthonormalized(rotate_axis(f, axis / s, std::atan2(s, glm::dot(f.z, to))));
}

// §4.8: turns f up by `angle_rad` (down when negative) about the horizontal axis across its z axis.
Frame turn_up(const Frame& f, float angle_rad) {
  const Vec3 across{-f.z.y, f.z.x, 0.0f};
  const float l = glm::length(across);
  if (l < 1e-6f) return f;
  return rotate_axis(f, across / l, -angle_rad);
}

// A stem on flat ground: a segment of length `seg_len` from `start` whose end would come closer to
// the ground than `clearance` (its radius there) is turned up, keeping its heading, just enough to
// stay at that height; the stem then goes on from the turned frame, as if grown along the ground.
Frame keep_above_ground(const Frame& f, const Vec3& start, float seg_len, float clearance) {
  if (seg_len <= 0.0f) return f;
  const float need = (clearance - start.z) / seg_len;  // the least z component of the direction
  if (f.z.z >= need) return f;
  const float up = std::min(need, 1.0f);
  Vec3 heading{f.z.x, f.z.y, 0.0f};
  const float h = glm::length(heading);
  heading = h > 1e-6f ? heading / h : Vec3(1.0f, 0.0f, 0.0f);
  return turn_to(f, heading * std::sqrt(std::max(0.0f, 1.0f - up * up)) + Vec3(0.0f, 0.0f, up));
}

// A stem (or a clone) ready to be formed from segment `segment` on.
struct StemState {
  int level = 0;
  int parent = -1;
  int clone_of = -1;
  Vec3 pos{0.0f};
  Frame section_frame;  // frame of the first cross-section
  Frame frame;          // frame the next segment's curvature is applied to
  Frame helix_frame;    // the stem's frame at segment 0 (helix mode, nCurveV < 0)
  int segment = 0;
  float length = 0.0f;
  float base_radius = 0.0f;
  float offset = 0.0f;  // along the parent
  float parent_length = 0.0f;
  float length_child_max = 1.0f;
  float split_correction_deg = 0.0f;
  int plan_node = -1;  // this stem's entry in its family's split plan (Builder::plan_family)
  uint64_t seed = 0;
  Pcg32 rng;
  float sway_offset_x = 0.0f, sway_offset_y = 0.0f;
  float children_per_segment = 0.0f;  // trunk: children per metre above BaseSize
  float leaves_per_segment = 0.0f;
  float child_carry = 0.0f, leaf_carry = 0.0f;
  float rotate_deg = 0.0f, leaf_rotate_deg = 0.0f;
  int alternate = 1, leaf_alternate = 1;
  uint32_t child_counter = 0;
};

// A formed segment with the child and leaf counts it carries: those of the stem when the segment
// was formed, before a split at its end divides them (Arbaro spawns per segment, then splits).
struct SegmentStart {
  Vec3 pos;
  Frame frame;
  int index;
  float children = 0.0f;
  float leaves = 0.0f;
};

class Builder {
 public:
  enum class Lengths { Probe, Record, Replay };

  Builder(const WeberPennParams& params, uint64_t seed, TreeModel& model, Lengths lengths,
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

  void build() {
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

  float scale_tree() const { return scale_tree_; }

 private:
  // Per-stem random state drawn right after creation, in a fixed order.
  void init_random_state(StemState& s) {
    s.sway_offset_x = s.rng.uniform() * kTwoPi;
    s.sway_offset_y = s.rng.uniform() * kTwoPi;
    s.rotate_deg = s.rng.uniform() * 360.0f;
    s.leaf_rotate_deg = s.rng.uniform() * 360.0f;
    s.child_carry = s.rng.uniform();
    s.leaf_carry = s.rng.uniform();
    s.helix_frame = s.frame;
  }

  // §4.3 child counts and §4.5 leaf counts, per segment (the trunk: per metre above BaseSize).
  void init_counts(StemState& s) const {
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
          count = wp::child_count_level1(branches, s.length, s.parent_length, s.length_child_max);
        else
          count = wp::child_count_deeper(branches, s.offset, s.parent_length);
        // Arbaro counts whole stems per stem (truncated; the guard keeps 29.99999 from becoming 29).
        if (p_.reading == wp::Reading::Arbaro) count = std::floor(count + 1e-4f);
        s.children_per_segment = std::max(0.0f, count) / static_cast<float>(n);
      }
    }
    if (s.level == p_.levels - 1 && p_.leaves > 0) {
      const float q = p_.quality * p_.leaf_quality;
      const float count =
          wp::leaf_count(p_.leaves, p_.leaf_distrib, s.offset, s.level == 0 ? 0.0f : s.parent_length, q, p_.reading);
      s.leaves_per_segment = std::max(0.0f, count) / static_cast<float>(n);
    }
  }

  float radius_at(const StemState& s, float z) const {
    float r = wp::taper_radius(p_.at(s.level).taper, s.base_radius, s.length, z);
    if (s.level == 0) r *= wp::flare_scale(p_.flare, z);
    return r;
  }

  // Extra cross-sections inside segments where the radius is not linear in Z: the flared trunk
  // base, rounded ends (nTaper in (1, 3)) and periodic tapering (nTaper in (2, 3)).
  void make_z_samples(const StemState& s, std::vector<float>& zs) const {
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

  // Forms segments [s.segment, nCurveRes) of stem s (§4.1–4.2). Probe: only tests the points
  // against the pruning envelope, including every clone's, and returns the index of the first
  // segment reaching outside (−1 when all inside). Otherwise: appends the stem, spawns its
  // children and leaves (§4.3, §4.5), then forms its clones.
  int form(StemState s, bool probe) {
    const WeberPennLevel& lp = p_.at(s.level);
    const int n = std::max(1, lp.curve_res);
    const float seg_len = s.length / static_cast<float>(n);
    std::vector<float>& zs = z_samples_[static_cast<size_t>(s.level)];
    make_z_samples(s, zs);
    size_t zi = 0;
    const float z_begin = static_cast<float>(s.segment) / static_cast<float>(n);
    while (zi < zs.size() && zs[zi] <= z_begin + 1e-6f) ++zi;

    int stem_index = -1;
    std::vector<SegmentStart>& segs = segments_[static_cast<size_t>(s.level)];
    if (!probe) {
      segs.clear();
      stem_index = static_cast<int>(m_.stems.size());
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
    }

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
      // §4.1 curvature.
      if (lp.curve_v < 0.0f) {
        // Helix: the segments precess once about the stem's initial axis, tilted by |nCurveV|.
        const float turn = kTwoPi * (static_cast<float>(i) + 0.5f) / static_cast<float>(n);
        f = rotate_x(rotate_z(s.helix_frame, turn), radians(-lp.curve_v));
      } else if (i > 0) {
        // Every segment turns away from the previous one; the first keeps the direction the down
        // and rotate angles gave the stem (both readings, docs/weber_penn.md).
        float curve = wp::segment_curve_deg(lp.curve, lp.curve_back, n, i) + s.split_correction_deg;
        // "A random rotation of magnitude nCurveV/nCurveRes is also added": a magnitude, its axis
        // random across the stem, in both readings (as Arbaro's newDirection; docs/weber_penn.md).
        const float random_deg = lp.curve_v / static_cast<float>(n) * s.rng.symmetric();
        f = rotate_x(f, radians(curve));
        const float about = s.rng.uniform() * kTwoPi;
        f = rotate_axis(f, f.x * std::cos(about) + f.y * std::sin(about), radians(random_deg));
      }
      // §4.8 vertical attraction, levels ≥ 2, about the horizontal axis across the stem.
      if (i > 0 && s.level >= 2 && p_.attraction_up != 0.0f)
        f = turn_up(f, wp::attraction_up_rad(p_.attraction_up, f.z.z, n));
      // §4.7 wind sway about the segment's x and y axes.
      if (p_.wind.active()) {
        const wp::Sway sway =
            wp::sway_angles(s.length, s.base_radius, radius_at(s, z0), z0, n, p_.wind.speed, p_.wind.gust,
                            p_.wind.time_s, p_.wind.time_scale, s.sway_offset_x, s.sway_offset_y);
        f = rotate_y(rotate_x(f, radians(sway.x_deg)), radians(sway.y_deg));
      }
      f = orthonormalized(f);
      // The clearance is the segment's larger end radius: the rings of a rounded tip (nTaper > 1)
      // inside the last segment are wider than its end.
      if (ground_) f = keep_above_ground(f, pos, seg_len, std::max(radius_at(s, z0), radius_at(s, z1)));

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
  void split(StemState& s, Frame& f, const Vec3& at, int i, int n, int splits, int stem_index,
             std::vector<StemState>& clones, size_t& clone_cursor) {
    const WeberPennLevel& lp = p_.at(s.level);
    const float declination = degrees(safe_acos(f.z.z));
    const float angle = wp::split_angle_deg(lp.split_angle, lp.split_angle_v, s.rng.symmetric(), declination);
    const float remaining = static_cast<float>(n - 1 - i);
    const float correction = remaining > 0.0f ? -angle / remaining : 0.0f;
    float spread = 0.0f;
    if (splits == 1) {
      const float sign = s.rng.uniform() < 0.5f ? -1.0f : 1.0f;
      spread = 0.5f * sign * wp::split_spread_deg(declination, s.rng.uniform());
    }
    // The stem and its clones share the children the stem would have carried over its remaining
    // segments (as Arbaro does). The paper reading shares the leaves too (docs/weber_penn.md,
    // "Readings"); Arbaro gives every clone the full leaf count.
    const float share = 1.0f / static_cast<float>(splits + 1);
    s.children_per_segment *= share;
    if (p_.reading == wp::Reading::Paper) s.leaves_per_segment *= share;
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

  // One entry of a family's split plan: the splits a stem makes at the end of each of its segments
  // from `first_segment` on, and the plan entries of its clones in the order it makes them.
  struct SplitNode {
    int first_segment = 0;
    std::vector<int> splits;
    std::vector<int> clones;
  };

  // §4.2 splits of a stem and all its clones (a family), decided in Arbaro's order (makeClones): the
  // stem decides segment by segment, and each clone, made at once, decides all of its own before
  // the stem goes on; the level's error value runs through the decisions in that order. Sylva forms
  // a stem's segments before its clones, so the decisions are made first and read back (the order
  // matters: with 1SegSplits = 0.25 over 17 segments a family has 24 stems one way, 28 the other).
  // Pruning probes read the plan without using up error. Returns the root's entry, or −1 when the
  // level never splits.
  int plan_family(int level) {
    const bool base_splits = level == 0 && p_.base_splits > 0;
    if (!base_splits && p_.at(level).seg_splits <= 0.0f) return -1;
    plan_size_[static_cast<size_t>(level)] = 0;
    return plan_stem(level, 0, base_splits, false, plans_[static_cast<size_t>(level)]);
  }
  int plan_stem(int level, int first_segment, bool base_splits, bool halved, std::vector<SplitNode>& plan) {
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
        splits = wp::diffuse_splits(lp.seg_splits * (halved ? 0.5f : 1.0f), split_error_[static_cast<size_t>(level)]);
      }
      plan[static_cast<size_t>(id)].splits.push_back(splits);
      if (splits == 0) continue;
      // §4.3 "any stem that has been cloned or is, itself, a clone reduces its propensity to form
      // clones by half": the paper reading; Arbaro never halves.
      halved = p_.reading == wp::Reading::Paper;
      for (int c = 0; c < splits; ++c) {
        const int clone = plan_stem(level, i + 1, false, halved, plan);
        plan[static_cast<size_t>(id)].clones.push_back(clone);
      }
    }
    return id;
  }

  // §4.3 children and §4.5 leaves along the segments just formed, each segment with the counts it
  // had when it was formed (a split divides the counts of the segments above it only).
  void spawn_children(StemState& s, int stem_index, float seg_len, const Vec3& tip, const Frame& tip_frame) {
    const int next = s.level + 1;
    std::vector<SegmentStart>& segs = segments_[static_cast<size_t>(s.level)];
    if (next < p_.levels) {
      const WeberPennLevel& lc = p_.at(next);
      if (lc.branches < 0) {
        fan_children(s, stem_index, tip, tip_frame);
      } else {
        for (size_t si = 0; si < segs.size(); ++si) {
          const SegmentStart seg = segs[si];  // copy: children reuse deeper scratch only
          float lo = static_cast<float>(seg.index) * seg_len;
          const float hi = lo + seg_len;
          float count = seg.children;
          if (s.level == 0) {
            lo = std::max(lo, length_base_);
            count = hi > lo ? seg.children * (hi - lo) : 0.0f;
          }
          if (hi <= lo) continue;
          const float total = count + s.child_carry;
          const int k = static_cast<int>(std::floor(total));
          s.child_carry = total - static_cast<float>(k);
          for (int j = 0; j < k; ++j) {
            const float t = lc.branch_dist * (static_cast<float>(j) + 0.5f) / static_cast<float>(k);
            const float offset = lo + t * (hi - lo);
            const Vec3 pos = seg.pos + seg.frame.z * (offset - static_cast<float>(seg.index) * seg_len);
            spawn_child(s, stem_index, seg.frame, pos, offset, 0.0f, false);
          }
        }
      }
    }
    if (s.level == p_.levels - 1 && p_.leaves != 0) {
      if (p_.leaves < 0) {
        fan_leaves(s, stem_index, tip, tip_frame);
        return;
      }
      for (size_t si = 0; si < segs.size(); ++si) {
        const SegmentStart& seg = segs[si];
        const float total = seg.leaves + s.leaf_carry;
        const int k = static_cast<int>(std::floor(total));
        s.leaf_carry = total - static_cast<float>(k);
        for (int j = 0; j < k; ++j) {
          const float t = (static_cast<float>(j) + 0.5f) / static_cast<float>(k);
          const float offset = (static_cast<float>(seg.index) + t) * seg_len;
          add_leaf(s, stem_index, seg.frame, seg.pos + seg.frame.z * (t * seg_len), offset, false, 0.0f);
        }
      }
    }
  }

  // Negative nBranches (§4.5): |nBranches| children in a fan of nRotate degrees at the stem end.
  void fan_children(StemState& s, int stem_index, const Vec3& tip, const Frame& f) {
    const WeberPennLevel& lc = p_.at(s.level + 1);
    const int count = -lc.branches;
    for (int j = 0; j < count; ++j) {
      const float a =
          count > 1 ? -0.5f * lc.rotate + lc.rotate * static_cast<float>(j) / static_cast<float>(count - 1) : 0.0f;
      spawn_child(s, stem_index, f, tip, s.length, a, true);
    }
  }

  void spawn_child(StemState& s, int stem_index, const Frame& parent_frame, const Vec3& pos, float offset,
                   float fan_deg, bool fan) {
    StemState c;
    c.level = s.level + 1;
    c.parent = stem_index;
    c.seed = hash_ids(s.seed, 0xB4Aull, static_cast<uint64_t>(s.child_counter++));
    c.rng = Pcg32(c.seed);
    const WeberPennLevel& lp = p_.at(c.level);
    // §4.3 length_child_max = nLength ± nLengthV, drawn per child.
    const float lcm = lp.length + lp.length_v * c.rng.symmetric();
    float length = s.level == 0
                       ? wp::child_length_level1(p_.shape, p_.envelope, s.length, length_base_, lcm, offset, p_.reading)
                       : wp::child_length_deeper(lcm, s.length, offset);
    // §4.3 down and rotate angles.
    const float parent_base = s.level == 0 ? length_base_ : 0.0f;
    const float span = s.length - parent_base;
    const float ratio = span > 0.0f ? (s.length - offset) / span : 0.0f;
    const float u_down = c.rng.symmetric();
    const float u_rot = c.rng.symmetric();
    const Frame f =
        orient_child(parent_frame, lp, p_.reading, ratio, u_down, u_rot, fan, fan_deg, s.rotate_deg, s.alternate);
    c.pos = pos;
    c.section_frame = c.frame = orthonormalized(f);
    c.offset = offset;
    c.parent_length = s.length;
    c.length_child_max = lcm;
    init_random_state(c);
    if (length < kMinStemLength) return;

    // §4.4 radius, limited to the parent's radius at the spawn point (for a fan at the tip of a
    // tapered stem, at the middle of its last segment, where the fan's stems emerge from the bark).
    const int parent_segments = std::max(1, p_.at(s.level).curve_res);
    const float spawn_z =
        fan ? 1.0f - 0.5f / static_cast<float>(parent_segments) : std::clamp(offset / s.length, 0.0f, 1.0f);
    const float parent_r = wp::taper_radius(p_.at(s.level).taper, s.base_radius, s.length, spawn_z);
    auto radius_for = [&](float l) {
      return std::min(wp::child_radius(s.base_radius, l, s.length, p_.ratio_power), parent_r);
    };
    c.length = length;
    c.base_radius = radius_for(length);
    // A stem pruned away is not made and leaves the split error as it was (Arbaro restores it).
    const float split_error = split_error_[static_cast<size_t>(c.level)];
    c.plan_node = plan_family(c.level);
    if (p_.prune_ratio > 0.0f) length = prune(c);
    c.length = length;
    c.base_radius = radius_for(length);
    if (length < kMinStemLength || c.base_radius < kMinStemRadius) {
      split_error_[static_cast<size_t>(c.level)] = split_error;
      return;
    }
    init_counts(c);
    form(c, false);
  }

  // §4.6 two-pass pruning: probe the stem (with its clones) without children, shrink it until
  // every point is inside the envelope, then blend with the unpruned length by PruneRatio.
  float prune(const StemState& c) {
    if (lengths_ == Lengths::Replay && replay_pos_ < pruned_->size()) return (*pruned_)[replay_pos_++];
    const float original = c.length;
    float length = original;
    StemState t = c;
    for (int iteration = 0; iteration < 64 && length >= kMinPrunedLength; ++iteration) {
      t.length = length;
      probe_budget_ = kMaxStems - std::min(kMaxStems, m_.stems.size());
      const int out = form(t, true);
      if (out < 0) break;
      const int n = std::max(1, p_.at(c.level).curve_res);
      length *= std::clamp(static_cast<float>(out) / static_cast<float>(n), 0.5f, 0.9f);
    }
    if (length < kMinPrunedLength) length = 0.0f;
    const float result = original + (length - original) * p_.prune_ratio;
    if (lengths_ == Lengths::Record) pruned_->push_back(result);
    return result;
  }

  bool inside(const Vec3& q) const { return wp::inside_envelope(q, scale_tree_, p_.base_size, p_.envelope); }

  // §4.5 leaves, with the leaf level's down and rotate angles, oriented by §4.9.
  void add_leaf(StemState& s, int stem_index, const Frame& parent_frame, const Vec3& axis_pos, float offset, bool fan,
                float fan_deg) {
    const WeberPennLevel& lp = p_.at(p_.levels);
    if (m_.leaves.size() >= kMaxWeberPennLeaves)
      throw Error("tree too large: more than " + std::to_string(kMaxWeberPennLeaves) +
                  " leaves (lower Leaves, nBranches or the quality factor)");
    Pcg32 rng(hash_ids(s.seed, 0x1EAFull, static_cast<uint64_t>(m_.leaves.size())));
    const float ratio = s.length > 0.0f ? (s.length - offset) / s.length : 0.0f;
    const float u_down = rng.symmetric();
    const float u_rot = rng.symmetric();
    Frame f = orient_child(parent_frame, lp, p_.reading, ratio, u_down, u_rot, fan, fan_deg, s.leaf_rotate_deg,
                           s.leaf_alternate);
    const float length = leaf_length_, width = leaf_width_;
    const Vec3 pos = axis_pos + f.z * (p_.leaf_stem_len * length);
    bend_leaf(f, pos);
    const Vec3 at = ground_ ? lift_leaf(f, pos, length, width) : pos;
    TreeLeaves& l = m_.leaves;
    l.positions.push_back(at);
    l.frames.push_back(f);
    l.length_m.push_back(length);
    l.width_m.push_back(width);
    l.shapes.push_back(p_.leaf_shape);
    l.stem.push_back(stem_index);
  }

  // Negative Leaves (§4.5): |Leaves| leaves in a fan of nRotate degrees at the stem end.
  void fan_leaves(StemState& s, int stem_index, const Vec3& tip, const Frame& f) {
    const WeberPennLevel& lp = p_.at(p_.levels);
    // As many as along a stem: |Leaves|·ShapeRatio(LeafDistrib, offset/length_parent)·quality, rounded
    // (Arbaro's makeLeaves, fan mode).
    const float per_stem = wp::leaf_count(-p_.leaves, p_.leaf_distrib, s.offset, s.level == 0 ? 0.0f : s.parent_length,
                                          p_.quality * p_.leaf_quality, p_.reading);
    const int count = static_cast<int>(std::floor(per_stem + 0.5f));
    for (int j = 0; j < count; ++j) {
      const float a =
          count > 1 ? -0.5f * lp.rotate + lp.rotate * static_cast<float>(j) / static_cast<float>(count - 1) : 0.0f;
      add_leaf(s, stem_index, f, tip, s.length, true, a);
    }
  }

  // A leaf whose quad (tree_mesher: `width` across −x centred on `pos`, `length` along z) would
  // reach below the ground points up instead; if it still would, it is lifted to the ground.
  static Vec3 lift_leaf(Frame& f, Vec3 pos, float length, float width) {
    auto lowest = [&] { return pos.z - 0.5f * width * std::abs(f.x.z) + std::min(0.0f, f.z.z * length); };
    if (lowest() >= 0.0f) return pos;
    if (f.z.z < 0.0f) f = turn_to(f, Vec3(f.z.x, f.z.y, -f.z.z));
    if (lowest() < 0.0f) pos.z -= lowest();
    return pos;
  }

  // §4.9: turn the leaf's normal (frame y) toward the outside about the vertical, then up toward
  // the sky, each by the fraction LeafBend of the full angle (angles wrapped to (−π, π]).
  void bend_leaf(Frame& f, const Vec3& pos) const {
    const float bend = p_.leaf_bend;
    if (bend == 0.0f) return;
    // theta_bend = theta_position − atan2(n_y, n_x), as one wrapped atan2 of the 2-D vectors.
    Vec3 normal = f.y;
    const float cross_z = normal.x * pos.y - normal.y * pos.x;
    const float dot_xy = normal.x * pos.x + normal.y * pos.y;
    if (cross_z != 0.0f || dot_xy != 0.0f) {
      f = rotate_about_vertical(f, bend * std::atan2(cross_z, dot_xy));
      normal = f.y;
    }
    // phi_bend = atan2(sqrt(n_x² + n_y²), n_z), turned about the horizontal axis n × Z.
    const float horizontal = std::sqrt(normal.x * normal.x + normal.y * normal.y);
    if (horizontal > 1e-6f) {
      const Vec3 axis{normal.y / horizontal, -normal.x / horizontal, 0.0f};
      f = rotate_axis(f, axis, bend * std::atan2(horizontal, normal.z));
    }
  }

  void emit(const Vec3& pos, const Frame& f, float radius, float arc) {
    m_.sections.positions.push_back(pos);
    m_.sections.frames.push_back(f);
    m_.sections.radius_m.push_back(radius);
    m_.sections.arc_m.push_back(arc);
  }

  // ZScale ± ZScaleV scales the finished tree vertically (docs/design.md §5.1).
  void finish() {
    if (z_scale_ == 1.0f) return;
    auto scale_frame = [&](Frame& f) {
      f.z = glm::normalize(Vec3(f.z.x, f.z.y, f.z.z * z_scale_));
      f.x = Vec3(f.x.x, f.x.y, f.x.z * z_scale_);
      f = orthonormalized(f);
    };
    for (Vec3& q : m_.sections.positions) q.z *= z_scale_;
    for (Frame& f : m_.sections.frames) scale_frame(f);
    for (Vec3& q : m_.leaves.positions) q.z *= z_scale_;
    for (Frame& f : m_.leaves.frames) scale_frame(f);
  }

  const WeberPennParams& p_;
  uint64_t seed_;
  TreeModel& m_;
  Lengths lengths_;
  std::vector<float>* pruned_;
  size_t probe_budget_ = 0;  // stems the running pruning probe may still form (kMaxStems less those made)
  size_t replay_pos_ = 0;
  bool ground_ = true;  // keep every stem and leaf above z = 0
  float scale_tree_ = 1.0f;
  float z_scale_ = 1.0f;
  float length_base_ = 0.0f;
  float leaf_length_ = 0.0f, leaf_width_ = 0.0f;
  std::vector<float> split_error_;                   // §4.2 error diffusion, per level
  std::vector<std::vector<SplitNode>> plans_;        // the split plan of the family being formed, per level
  std::vector<size_t> plan_size_;                    // entries of plans_ in use, per level
  std::vector<std::vector<SegmentStart>> segments_;  // scratch per level
  std::vector<std::vector<float>> z_samples_;        // scratch per level
};

}  // namespace

TreeModel make_weber_penn_tree(const WeberPennParams& params, uint64_t seed) {
  TreeModel model;
  if (params.wind.active() && params.prune_ratio > 0.0f) {
    // Prune the windless tree and reuse its stem lengths, so that the wind moves the stems
    // without changing the tree's structure (docs/design.md §5.1: same seed ⇒ same tree).
    WeberPennParams calm = params;
    calm.wind = {};
    std::vector<float> lengths;
    TreeModel scratch;
    Builder(calm, seed, scratch, Builder::Lengths::Record, &lengths).build();
    Builder(params, seed, model, Builder::Lengths::Replay, &lengths).build();
    return model;
  }
  Builder(params, seed, model, Builder::Lengths::Probe, nullptr).build();
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
