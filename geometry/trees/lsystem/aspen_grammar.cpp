#include "geometry/trees/lsystem/aspen_grammar.h"

#include "core/error.h"
#include "core/rng.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace sylva {

namespace {

constexpr size_t kMaxStems = 200'000;
constexpr size_t kMaxSections = 4'000'000;
constexpr Vec3 kUp{0, 0, 1};

// One <root> still to be grown.
struct Pending {
  Vec3 base;
  Vec3 dir;
  Vec3 ref;        // a direction across `dir`, carried from the parent (the divergence reference)
  float diameter;  // at the root, units
  float length;    // units
  int generation;
  int parent;
  float offset;  // arc along the parent, units
  bool dead;
  int record = -1;  // index in the trace, when tracing
};

Vec3 across(const Vec3& dir, const Vec3& hint) {
  Vec3 r = hint - dir * glm::dot(hint, dir);
  if (glm::length(r) < 1e-4f) r = glm::cross(dir, std::abs(dir.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0));
  return glm::normalize(r);
}

// Self-adjustment ("lifting"): the direction with its vertical component raised to `min_z`,
// keeping its horizontal heading (or `fallback`'s when it points straight down).
Vec3 lift(const Vec3& dir, float min_z, const Vec3& fallback) {
  Vec3 h(dir.x, dir.y, 0.0f);
  if (glm::length(h) < 1e-6f) h = Vec3(fallback.x, fallback.y, 0.0f);
  if (glm::length(h) < 1e-6f) h = Vec3(1, 0, 0);
  const Vec3 flat = glm::normalize(h) * std::sqrt(std::max(0.0f, 1.0f - min_z * min_z));
  return Vec3(flat.x, flat.y, min_z);
}

// Eqs. 6.2–6.7: rotate the parent direction onto the axis, apply the branch angle and then the
// divergence angle, undo the preliminary rotations. In a frame (ref, dir × ref, dir) about the
// parent direction that composite is this spherical direction.
Vec3 child_direction(const Vec3& parent_dir, const Vec3& ref, float branch_angle_rad, float divergence_rad) {
  const Vec3 side = glm::cross(parent_dir, ref);
  const Vec3 out = ref * std::cos(divergence_rad) + side * std::sin(divergence_rad);
  return glm::normalize(parent_dir * std::cos(branch_angle_rad) + out * std::sin(branch_angle_rad));
}

class AspenGrower {
 public:
  AspenGrower(const AspenGrammarParams& p, uint64_t seed, AspenGrammarTrace* trace)
      : p_(p), seed_(seed), trace_(trace) {}

  TreeModel grow() {
    queue_.push_back(Pending{Vec3(0), kUp, Vec3(1, 0, 0), p_.diameter, p_.height, 0, -1, 0.0f, false, -1});
    // Depth-first over <root>s: every stem's sections are written before its children's.
    while (!queue_.empty()) {
      const Pending next = queue_.back();
      queue_.pop_back();
      grow_root(next);
    }
    return std::move(m_);
  }

 private:
  // Where the walk along a <root> is: the point, the trunk's unbumped axis point, the direction,
  // the last segment's direction, the divergence reference, the arc walked (units, nominal and
  // actual), and the children's azimuths.
  struct Walk {
    Vec3 point, axis, dir, seg, ref;
    float s = 0, arc = 0;
    float shrinkage = 0;
    int child_number = 0;
    float azimuth = 0, previous_azimuth = 0;
  };

  // One <root>: its <linear_pt>s, the children of their <circle_pt>s, and its <linear_tail>.
  void grow_root(const Pending& r) {
    const int stem = begin_stem(r);
    Pcg32 rng(hash_ids(seed_, 0xA59E4ull, static_cast<uint64_t>(stem)));
    const bool trunk = r.generation == 0;
    Walk w{r.base, r.base, r.dir, r.dir, across(r.dir, r.ref)};
    w.shrinkage = trunk ? p_.trunk_shrinkage : p_.branch_shrinkage;
    push_section(w, r.diameter);
    w.azimuth = rng.uniform(0.0f, kTwoPi);
    for (int n = 1; w.s < r.length; ++n) {
      advance(r, w, n, rng);
      const bool tip = w.s >= r.length;
      const float d_here = diameter_at(r, w, std::min(w.s, r.length));
      push_section(w, d_here);
      if (tip) break;
      if (p_.shoot_generation > 0 && r.generation >= p_.shoot_generation && !r.dead)
        add_leaf_cluster(w.point, w.dir, stem, rng);
      // Child branching (§ "Child Branching"): none past the last generation, on the trunk's
      // first points or below the minimum diameter; otherwise a random choice.
      if (r.generation >= p_.generations || r.dead) continue;
      if (trunk && n < p_.first_trunk_point) continue;
      if (d_here < p_.min_diameter) continue;
      branch(r, w, stem, d_here, rng);
    }
    TreeStems& st = m_.stems;
    st.section_count.back() = static_cast<uint32_t>(m_.sections.size()) - st.first_section.back();
    if (r.dead) return;
    if (trunk) return add_leaf_cluster(w.point, w.dir, stem, rng);  // the leader's tip
    grow_tail(r, w, stem, rng);
  }

  // Adds <root> r's stem (no sections yet) and returns its index.
  int begin_stem(const Pending& r) {
    const int stem = static_cast<int>(m_.stems.size());
    if (m_.stems.size() >= kMaxStems)
      throw Error("tree too large: more than " + std::to_string(kMaxStems) +
                  " stems (lower generations or branch_probability, or raise min_diameter)");
    if (trace_ != nullptr && r.record >= 0) trace_->children[static_cast<size_t>(r.record)].stem = stem;
    const float u = p_.unit_m;
    TreeStems& st = m_.stems;
    st.level.push_back(static_cast<uint8_t>(std::min(r.generation, 255)));
    st.parent.push_back(r.parent);
    st.clone_of.push_back(-1);
    st.first_section.push_back(static_cast<uint32_t>(m_.sections.size()));
    st.section_count.push_back(0);
    st.length_m.push_back(r.length * u);
    st.base_radius_m.push_back(0.5f * r.diameter * u);
    st.offset_m.push_back(r.offset * u);
    st.lobes.push_back(0);
    st.lobe_depth.push_back(0);
    st.dead.push_back(r.dead ? 1 : 0);
    return stem;
  }

  // Eqs. 6.9, 6.10: the girth at arc `at`.
  static float diameter_at(const Pending& r, const Walk& w, float at) {
    return r.diameter * (1.0f - w.shrinkage * at / r.length);
  }

  // A cross-section of diameter d at the walk's point.
  void push_section(const Walk& w, float d) {
    const float u = p_.unit_m;
    if (m_.sections.size() >= kMaxSections)
      throw Error("tree too large: more than " + std::to_string(kMaxSections) +
                  " cross-sections (raise point_spacing or lower height)");
    m_.sections.positions.push_back(w.point * u);
    const Vec3 x = across(w.seg, w.ref);
    m_.sections.frames.push_back(Frame{x, glm::cross(w.seg, x), w.seg});
    m_.sections.radius_m.push_back(0.5f * d * u);
    m_.sections.arc_m.push_back(w.arc * u);
  }

  // The walk to the n-th <linear_pt>: a step set by the girth, sagging and lifted (branches), bumped
  // every bump_every points.
  void advance(const Pending& r, Walk& w, int n, Pcg32& rng) const {
    const bool trunk = r.generation == 0;
    const float d = diameter_at(r, w, w.s);
    // "The distance between linear points is determined by the diameter of the object at this
    // point plus the generation."
    float step = std::max(p_.point_spacing * d + p_.point_spacing_generation * static_cast<float>(r.generation),
                          1e-3f * r.length);
    if (r.length - w.s < 1.25f * step) step = r.length - w.s;
    // Self-adjustment (lifting): gravity sags the direction; a drooping one is lifted.
    if (!trunk) {
      w.dir.z -= p_.sag;
      w.dir = w.dir.z < p_.droop_limit ? lift(w.dir, p_.droop_limit, w.ref) : glm::normalize(w.dir);
    }
    // Eq. 6.1: L(n+1) = L(n) + V × distance + B, the bump B every fifth point: the two minor
    // components of the direction move by a random amount scaled by the diameter. The trunk's
    // points stay about its axis ("linear points that are part of the trunk ... lie along the
    // y axis"): its bumps are offsets from the axis, not turns.
    w.axis += w.dir * step;
    Vec3 next = trunk ? w.axis : w.point + w.dir * step;
    if (p_.bump_every > 0 && n % p_.bump_every == 0) {
      const Vec3 a = glm::abs(w.dir);
      const int major = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
      for (int k = 0; k < 3; ++k)
        if (k != major) next[k] += p_.bump * d * rng.symmetric();
    }
    const float moved_len = glm::length(next - w.point);
    w.seg = (next - w.point) / moved_len;
    if (!trunk) {
      w.dir = w.seg;
      if (w.dir.z < p_.droop_limit) {  // the bump may not undo the lifting
        w.dir = w.seg = lift(w.dir, p_.droop_limit, w.ref);
        next = w.point + w.dir * moved_len;
      }
    }
    w.ref = across(w.dir, w.ref);
    w.point = next;
    w.s += step;
    w.arc += moved_len;
  }

  // <linear_pt> -> <circle_pt>^8, <circle_pt> -> <bark> | <bark><root>: each of the eight circle
  // points may carry a child object.
  void branch(const Pending& r, Walk& w, int stem, float d_here, Pcg32& rng) {
    for (int circle_pt = 0; circle_pt < 8; ++circle_pt) {
      const float choice = rng.uniform();
      if (choice >= p_.branch_probability + p_.dead_probability) continue;
      const bool dead = choice >= p_.branch_probability;
      const int generation = r.generation + 1;
      const int number = w.child_number + 1;
      // Eq. 6.12 on the parent's length beyond the branch point (docs/lsystems.md).
      float length = p_.length_ratio * (r.length - w.s) - static_cast<float>(number) * p_.length_child_term -
                     static_cast<float>(generation) * p_.length_generation_term;
      if (dead) length *= p_.dead_length;
      length = std::max(length, p_.min_length);  // self-adjustment: "must be longer than 6.0"
      w.child_number = number;
      // Eq. 6.13.
      const float ratio = 1.0f - rng.uniform(p_.diameter_contraction_min, p_.diameter_contraction_max);
      // Eq. 6.14 (radians), never below the minimum angle.
      const float angle = std::max(radians(p_.branch_angle_base_deg) - (p_.branch_angle_child_rad * number +
                                                                        p_.branch_angle_generation_rad * generation),
                                   p_.min_branch_angle_rad);
      float step_deg = 0;
      if (number > 1) {
        step_deg = p_.divergence_deg + p_.divergence_noise_deg * rng.symmetric();
        w.azimuth = w.previous_azimuth + radians(step_deg);
      }
      w.previous_azimuth = w.azimuth;
      const Vec3 cdir = child_direction(w.dir, w.ref, angle, w.azimuth);
      add_child(Pending{w.point, cdir, w.dir, ratio * d_here, length, generation, stem, w.arc, dead, -1},
                AspenChildRecord{0, stem, generation, number, dead, false, step_deg, angle, ratio, length});
    }
  }

  // <linear_tail>: a fork (da Vinci's rule, eq. 6.8 with α = 2) or a leaf cluster.
  void grow_tail(const Pending& r, const Walk& w, int stem, Pcg32& rng) {
    const float d_tip = diameter_at(r, w, r.length);
    if (r.generation < p_.generations && d_tip >= p_.min_diameter && rng.uniform() < p_.fork_probability) {
      const float share = rng.uniform(0.3f, 0.7f);
      const float angle = std::max(radians(p_.branch_angle_base_deg) * 0.5f -
                                       p_.branch_angle_generation_rad * static_cast<float>(r.generation + 1),
                                   p_.min_branch_angle_rad);
      const float length = std::max(
          p_.length_ratio * r.length - static_cast<float>(r.generation + 1) * p_.length_generation_term, p_.min_length);
      const float az = rng.uniform(0.0f, kTwoPi);
      for (int k = 0; k < 2; ++k) {
        const float d = d_tip * std::sqrt(k == 0 ? share : 1.0f - share);
        const Vec3 cdir = child_direction(w.dir, w.ref, angle, az + kPi * static_cast<float>(k));
        add_child(Pending{w.point, cdir, w.dir, d, length, r.generation + 1, stem, w.arc, false, -1},
                  AspenChildRecord{0, stem, r.generation + 1, 0, false, true, 0, angle, d / d_tip, length});
      }
      return;
    }
    add_leaf_cluster(w.point, w.dir, stem, rng);
  }

  void add_child(Pending child, const AspenChildRecord& record) {
    if (trace_ != nullptr) {
      child.record = static_cast<int>(trace_->children.size());
      trace_->children.push_back(record);
    }
    queue_.push_back(child);
  }

  // <leaf_clus>: leaves around the tip, petioles pointing away from it, blades facing mostly up.
  void add_leaf_cluster(const Vec3& tip, const Vec3& dir, int stem, Pcg32& rng) {
    const float u = p_.unit_m;
    for (int i = 0; i < p_.leaves_per_cluster; ++i) {
      Vec3 offset = symmetric3(rng);
      offset *= p_.cluster_radius_m;
      const Vec3 pos = tip * u + offset;
      Vec3 out = dir + symmetric3(rng) * 1.2f;
      out.z -= 0.3f;  // aspen leaves hang on long flattened petioles
      if (glm::length(out) < 1e-3f) out = dir;
      const Vec3 z = glm::normalize(out);
      const Vec3 y = across(z, kUp + Vec3(symmetric2(rng), 0.0f) * 0.5f);
      m_.leaves.positions.push_back(pos);
      m_.leaves.frames.push_back(Frame{glm::cross(y, z), y, z});
      const float size = rng.uniform(0.8f, 1.2f);
      m_.leaves.length_m.push_back(p_.leaf_length_m * size);
      m_.leaves.width_m.push_back(p_.leaf_width_m * size);
      m_.leaves.shapes.push_back(p_.leaf_shape);
      m_.leaves.stem.push_back(stem);
    }
  }

  const AspenGrammarParams& p_;
  uint64_t seed_;
  AspenGrammarTrace* trace_;
  TreeModel m_;
  std::vector<Pending> queue_;
};

}  // namespace

TreeModel make_aspen_grammar_tree(const AspenGrammarParams& params, uint64_t seed, AspenGrammarTrace* trace) {
  return AspenGrower(params, seed, trace).grow();
}

}  // namespace sylva
