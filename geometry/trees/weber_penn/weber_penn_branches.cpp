#include "core/error.h"
#include "geometry/trees/weber_penn/weber_penn_builder.h"
#include "geometry/trees/weber_penn/weber_penn_frames.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace sylva::wp {

// §4.3 children and §4.5 leaves along the segments just formed, each segment with the counts it
// had when it was formed (a split divides the counts of the segments above it only).
void Builder::spawn_children(StemState& s, int stem_index, float seg_len, const Vec3& tip, const Frame& tip_frame) {
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
void Builder::fan_children(StemState& s, int stem_index, const Vec3& tip, const Frame& f) {
  const WeberPennLevel& lc = p_.at(s.level + 1);
  const int count = -lc.branches;
  for (int j = 0; j < count; ++j) {
    const float a =
        count > 1 ? -0.5f * lc.rotate + lc.rotate * static_cast<float>(j) / static_cast<float>(count - 1) : 0.0f;
    spawn_child(s, stem_index, f, tip, s.length, a, true);
  }
}

void Builder::spawn_child(StemState& s, int stem_index, const Frame& parent_frame, const Vec3& pos, float offset,
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
                     ? child_length_level1(p_.shape, p_.envelope, s.length, length_base_, lcm, offset, p_.reading)
                     : child_length_deeper(lcm, s.length, offset);
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
  const float parent_r = taper_radius(p_.at(s.level).taper, s.base_radius, s.length, spawn_z);
  auto radius_for = [&](float l) {
    return std::min(child_radius(s.base_radius, l, s.length, p_.ratio_power), parent_r);
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
float Builder::prune(const StemState& c) {
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

// §4.5 leaves, with the leaf level's down and rotate angles, oriented by §4.9.
void Builder::add_leaf(StemState& s, int stem_index, const Frame& parent_frame, const Vec3& axis_pos, float offset,
                       bool fan, float fan_deg) {
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
void Builder::fan_leaves(StemState& s, int stem_index, const Vec3& tip, const Frame& f) {
  const WeberPennLevel& lp = p_.at(p_.levels);
  // As many as along a stem: |Leaves|·ShapeRatio(LeafDistrib, offset/length_parent)·quality, rounded
  // (Arbaro's makeLeaves, fan mode).
  const float per_stem = leaf_count(-p_.leaves, p_.leaf_distrib, s.offset, s.level == 0 ? 0.0f : s.parent_length,
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
Vec3 Builder::lift_leaf(Frame& f, Vec3 pos, float length, float width) {
  auto lowest = [&] { return pos.z - 0.5f * width * std::abs(f.x.z) + std::min(0.0f, f.z.z * length); };
  if (lowest() >= 0.0f) return pos;
  if (f.z.z < 0.0f) f = turn_to(f, Vec3(f.z.x, f.z.y, -f.z.z));
  if (lowest() < 0.0f) pos.z -= lowest();
  return pos;
}

// §4.9: turn the leaf's normal (frame y) toward the outside about the vertical, then up toward
// the sky, each by the fraction LeafBend of the full angle (angles wrapped to (−π, π]).
void Builder::bend_leaf(Frame& f, const Vec3& pos) const {
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

// ZScale ± ZScaleV scales the finished tree vertically (docs/design.md §5.1).
void Builder::finish() {
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

}  // namespace sylva::wp
