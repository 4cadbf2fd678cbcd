#pragma once
// The Weber & Penn (1995) tree builder: a stem, its segments, splits and clones (§4.1–4.2, in
// weber_penn.cpp), then its children, leaves and pruning (§4.3–4.6, §4.9, in
// weber_penn_branches.cpp), following Arbaro's order of random draws where the paper is silent
// (docs/weber_penn.md). Internal to geometry/trees/weber_penn/.

#include "core/rng.h"
#include "geometry/trees/weber_penn/weber_penn.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sylva::wp {

// Budgets that turn a runaway parameter set (e.g. nBranches in the hundreds of thousands on two
// levels) into a clear error instead of exhausting memory: far above any real tree (the Weeping
// Willow has 50k stems and 550k leaves).
inline constexpr size_t kMaxStems = 1'000'000;
inline constexpr size_t kMaxWeberPennLeaves = 10'000'000;

// Stems shorter or thinner than this are not formed (Arbaro's MIN_STEM_LEN and MIN_STEM_RADIUS:
// small plants such as Arbaro's rush have stems under a millimetre).
inline constexpr float kMinStemLength = 0.00001f;
inline constexpr float kMinStemRadius = 0.000001f;
// Pruning (§4.6) gives up on a stem shrunk below half a millimetre.
inline constexpr float kMinPrunedLength = 0.0005f;
// Rings of the trunk's flared base (flare_Z is non-trivial for Z < 1/8).
inline constexpr float kFlareZ[] = {0.005f, 0.012f, 0.022f, 0.035f, 0.05f, 0.07f, 0.095f, 0.125f};
// Rings of a rounded stem end (nTaper in (1, 3)).
inline constexpr int kTipRings = 6;

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

// One entry of a family's split plan: the splits a stem makes at the end of each of its segments
// from `first_segment` on, and the plan entries of its clones in the order it makes them.
struct SplitNode {
  int first_segment = 0;
  std::vector<int> splits;
  std::vector<int> clones;
};

class Builder {
 public:
  enum class Lengths { Probe, Record, Replay };

  Builder(const WeberPennParams& params, uint64_t seed, TreeModel& model, Lengths lengths,
          std::vector<float>* pruned_lengths);
  void build();
  float scale_tree() const { return scale_tree_; }

 private:
  // weber_penn.cpp: stems, segments and splits.
  void init_random_state(StemState& s);
  void init_counts(StemState& s) const;
  float radius_at(const StemState& s, float z) const {
    float r = taper_radius(p_.at(s.level).taper, s.base_radius, s.length, z);
    if (s.level == 0) r *= flare_scale(p_.flare, z);
    return r;
  }
  void make_z_samples(const StemState& s, std::vector<float>& zs) const;
  int form(StemState s, bool probe);
  int begin_stem(const StemState& s, float z_begin);
  Frame turn_segment(StemState& s, Frame f, const Vec3& pos, int i, int n, float seg_len) const;
  void split(StemState& s, Frame& f, const Vec3& at, int i, int n, int splits, int stem_index,
             std::vector<StemState>& clones, size_t& clone_cursor);
  int plan_family(int level);
  int plan_stem(int level, int first_segment, bool base_splits, bool halved, std::vector<SplitNode>& plan);
  void emit(const Vec3& pos, const Frame& f, float radius, float arc) {
    m_.sections.positions.push_back(pos);
    m_.sections.frames.push_back(f);
    m_.sections.radius_m.push_back(radius);
    m_.sections.arc_m.push_back(arc);
  }

  // weber_penn_branches.cpp: children, leaves, pruning and the finished tree's scale.
  void spawn_children(StemState& s, int stem_index, float seg_len, const Vec3& tip, const Frame& tip_frame);
  void fan_children(StemState& s, int stem_index, const Vec3& tip, const Frame& f);
  void spawn_child(StemState& s, int stem_index, const Frame& parent_frame, const Vec3& pos, float offset,
                   float fan_deg, bool fan);
  float prune(const StemState& c);
  bool inside(const Vec3& q) const { return inside_envelope(q, scale_tree_, p_.base_size, p_.envelope); }
  void add_leaf(StemState& s, int stem_index, const Frame& parent_frame, const Vec3& axis_pos, float offset, bool fan,
                float fan_deg);
  void fan_leaves(StemState& s, int stem_index, const Vec3& tip, const Frame& f);
  static Vec3 lift_leaf(Frame& f, Vec3 pos, float length, float width);
  void bend_leaf(Frame& f, const Vec3& pos) const;
  void finish();

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

}  // namespace sylva::wp
