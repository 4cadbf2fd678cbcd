#include "geometry/trees/treemaker/treemaker.h"

#include "core/error.h"
#include "core/rng.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace sylva {

namespace {

// Budgets that turn a runaway template (e.g. `number= 5 to 6` on every level for 20 iterations)
// into a clear error instead of exhausting memory: far above any template shipped (the dogwood
// has about a thousand particles).
constexpr size_t kMaxParticles = 250'000;
constexpr size_t kMaxSections = 5'000'000;
constexpr size_t kMaxTreeMakerLeaves = 5'000'000;

constexpr Vec3 kUp{0.0f, 0.0f, 1.0f};
// Below this horizontal length a direction counts as vertical: the particle's stored horizontal
// reference stands in for the side vector.
constexpr float kVertical = 1e-4f;

// Rodrigues rotation of v about the unit axis k by a radians.
Vec3 rotate_vector(const Vec3& v, const Vec3& k, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return v * c + glm::cross(k, v) * s + k * (glm::dot(k, v) * (1.0f - c));
}

Vec3 normalize_or(const Vec3& v, const Vec3& fallback) {
  const float l = glm::length(v);
  return l > 1e-12f ? v / l : fallback;
}

float draw(Pcg32& rng, const TreeMakerRange& r) { return r.lo == r.hi ? r.lo : rng.uniform(r.lo, r.hi); }

Vec3 normalised_rgb(const Vec3& rgb) {
  const float m = std::max({rgb.x, rgb.y, rgb.z});
  return m > 0.0f ? rgb / m : Vec3(0.0f);
}

// §II: "A width is stored for each of the particle's past positions, and these widths are
// incremented by an amount specified in the tree template"; §V: "the aging factor ... is added to
// the growth value" — so a position stored `increments` iterations before the end has the width
// Σ_{k<increments} max(0, growth + k·age). Closed form of that sum.
float accumulated_width(float growth, float age, int increments) {
  const double g = std::max(0.0f, growth), a = age;
  double m = std::max(0, increments);
  if (a < 0.0) m = std::min(m, std::ceil(g / -a));
  return static_cast<float>(m * g + a * m * (m - 1.0) / 2.0);
}

// Where a leaf definition goes: its origin at the branch end, its axes, metres per template unit.
struct Placement {
  Vec3 origin;
  Frame f;
  float unit_m;
  Vec3 point(const Vec3& q) const { return origin + f.to_world(q) * unit_m; }
  Vec3 vector(const Vec3& q) const { return f.to_world(q) * unit_m; }
};

// Templates from the parser are valid; a template built in code gets a clear error instead of an
// out-of-range colour.
void validate(const TreeMakerTemplate& t) {
  const auto valid_color = [&](int c) { return c >= 0 && static_cast<size_t>(c) < t.colors.size(); };
  for (const TreeMakerParticle& p : t.particles)
    if (!valid_color(p.color)) throw Error("TREE-MAKER template: a particle's color index is out of range");
  for (const TreeMakerLeaf& l : t.leaves)
    for (const TreeMakerElement& e : l.elements)
      if (!valid_color(e.color) || (e.points.size() != 2 && e.points.size() != 3))
        throw Error("TREE-MAKER template: a leaf element needs a valid color and 2 or 3 points");
}

struct Particle {
  int level = 0;
  int parent = -1;
  size_t parent_node = 0;  // the parent's stored position this particle starts from
  Vec3 pos{0.0f};
  Vec3 dir{0.0f, 0.0f, 1.0f};   // unit growth direction
  Vec3 side{1.0f, 0.0f, 0.0f};  // horizontal reference for a vertical direction
  TreeMakerRange magnitude;     // the growth vector's length is drawn from it every iteration
  float acc = 0.0f;
  float growth = 0.0f;
  float age = 0.0f;
  bool alive = true;
  Pcg32 rng;
  Vec3 start_dir{0.0f, 0.0f, 1.0f};
  std::vector<Vec3> nodes;     // stored positions (limb nodes), template units
  std::vector<int> node_born;  // iteration at which each was stored
};

class Grower {
 public:
  Grower(const TreeMakerTemplate& t, uint64_t seed) : t_(t), seed_(seed) {}

  TreeModel grow() {
    validate(t_);
    for (size_t i = 0; i < t_.particles.size(); ++i) add_start_particle(t_.particles[i]);
    // The growing particles in creation order; stopped ones drop out, so the cost follows the
    // live particles, not every particle ever made times the iterations.
    std::vector<size_t> growing, next;
    for (size_t i = 0; i < particles_.size(); ++i)
      if (particles_[i].alive) growing.push_back(i);
    for (int it = 1; it <= t_.iterations && !growing.empty(); ++it) {
      // Branches added during an iteration start moving in the next one.
      const size_t first_new = particles_.size();
      next.clear();
      for (const size_t i : growing) {
        step(i, it);
        if (particles_[i].alive) next.push_back(i);
      }
      for (size_t i = first_new; i < particles_.size(); ++i) next.push_back(i);
      std::swap(growing, next);
    }
    TreeModel model;
    emit_stems(model);
    emit_leaves(model);
    return model;
  }

 private:
  // Adds a particle with its own random stream (so a particle's draws do not depend on how many
  // particles grew before it in the same iteration).
  Particle& add_particle(Particle&& p) {
    if (particles_.size() >= kMaxParticles)
      throw Error("tree too large: more than " + std::to_string(kMaxParticles) +
                  " TREE-MAKER particles (lower the branch numbers or the iterations)");
    p.rng = Pcg32(hash_ids(seed_, 0x7ae3ull, particles_.size()));
    particles_.push_back(std::move(p));
    return particles_.back();
  }

  // §II: "the program starts with a single particle on the ground with a growth vector pointing
  // up, as specified in the tree template" — dir= is the direction, deviated by up to maxdev_angle.
  void add_start_particle(const TreeMakerParticle& tp) {
    Particle& p = add_particle(Particle{});
    p.pos = tp.pos;
    p.magnitude = tp.mag;
    const Vec3 d0 = normalize_or(tp.dir, kUp);
    const Frame f = Frame::from_z(d0);
    const float dev = radians(p.rng.uniform(0.0f, tp.max_dev_deg));
    const float phi = p.rng.uniform(0.0f, kTwoPi);
    p.dir = normalize_or(std::cos(dev) * d0 + std::sin(dev) * (std::cos(phi) * f.x + std::sin(phi) * f.y), d0);
    const float psi = p.rng.uniform(0.0f, kTwoPi);
    p.side = Vec3(std::cos(psi), std::sin(psi), 0.0f);
    p.acc = tp.acc;
    p.growth = tp.growth;
    p.age = tp.age;
    p.start_dir = p.dir;
    p.alive = p.magnitude.hi > 0.0f;
  }

  // The horizontal side vector and the upward perpendicular of a direction: `dir` angles are
  // measured about the limb from `side` (0°) through `up` (90°) to −side (180°).
  static void side_and_up(const Vec3& d, const Vec3& reference, Vec3& side, Vec3& up) {
    const Vec3 h = glm::cross(kUp, d);
    const float hl = glm::length(h);
    if (hl > kVertical) {
      side = h / hl;
    } else {
      side = normalize_or(reference - d * glm::dot(reference, d), Frame::from_z(d).x);
    }
    up = glm::cross(d, side);
  }

  // One iteration of one particle (§II): store the position, add the growth vector, shorten it by
  // the aging factor (acc=), bend it toward the ground by gravity, then branch.
  void step(size_t i, int iteration) {
    {
      Particle& p = particles_[i];
      if (++sections_ > kMaxSections)
        throw Error("tree too large: more than " + std::to_string(kMaxSections) +
                    " TREE-MAKER limb positions (lower the iterations or the branch numbers)");
      p.nodes.push_back(p.pos);
      p.node_born.push_back(iteration);
      // §V: the magnitude "varying between 15 and 25"; acc= "will reduce each limit of the range
      // by 0.8 at each iteration".
      p.pos += p.dir * draw(p.rng, p.magnitude);
      p.magnitude.lo = std::max(0.0f, p.magnitude.lo + p.acc);
      p.magnitude.hi += p.acc;
      if (!(p.magnitude.hi > 0.0f)) {
        p.magnitude = {0.0f, 0.0f};
        p.alive = false;
      }
      // §II and §V: gravity × the cosine of the angle between the growth vector and the
      // horizontal is subtracted from the vector's z-component, then the magnitude restored.
      const float cos_to_horizontal = std::sqrt(p.dir.x * p.dir.x + p.dir.y * p.dir.y);
      p.dir = normalize_or(p.dir - kUp * (t_.gravity * cos_to_horizontal), p.dir);
    }
    if (iteration < t_.iterations && particles_[i].alive) branch(i);
  }

  // §II branching: the rule of the new branches' level gives how many branches (the number range
  // truncated, §V) and, per branch, a triplet chosen by its probability with an angle from the
  // limb, a direction about it and a growth reduction factor.
  void branch(size_t i) {
    const int level = particles_[i].level + 1;
    const TreeMakerBranchRule* rule = t_.rule_for_level(level);
    if (rule == nullptr || rule->choices.empty()) return;
    const int n = std::max(0, static_cast<int>(draw(particles_[i].rng, rule->number)));
    for (int k = 0; k < n; ++k) {
      Particle& parent = particles_[i];
      const float u = parent.rng.uniform();
      size_t c = 0;
      float cumulative = rule->choices[0].p;
      while (u >= cumulative && c + 1 < rule->choices.size()) cumulative += rule->choices[++c].p;
      const TreeMakerBranchChoice& choice = rule->choices[c];
      const float angle = radians(draw(parent.rng, choice.angle_deg));
      const float dir = radians(draw(parent.rng, choice.dir_deg));
      const float factor = draw(parent.rng, choice.factor);
      Vec3 side, up;
      side_and_up(parent.dir, parent.side, side, up);
      const Vec3 around = std::cos(dir) * side + std::sin(dir) * up;
      const Vec3 child_dir = normalize_or(std::cos(angle) * parent.dir + std::sin(angle) * around, parent.dir);
      const TreeMakerRange magnitude{parent.magnitude.lo * factor, parent.magnitude.hi * factor};
      if (!(magnitude.hi > 0.0f)) continue;
      // The reduction applies to the growth vector, the lateral growth and their aging (§V:
      // "reduce the width and length of these limbs").
      Particle child;
      child.level = level;
      child.parent = static_cast<int>(i);
      child.parent_node = parent.nodes.size();
      child.pos = parent.pos;
      child.dir = child_dir;
      child.start_dir = child_dir;
      child.side = side;
      child.magnitude = magnitude;
      child.acc = parent.acc * factor;
      child.growth = parent.growth * factor;
      child.age = parent.age * factor;
      add_particle(std::move(child));
    }
  }

  void emit_stems(TreeModel& m) const {
    TreeStems& st = m.stems;
    StemSections& sec = m.sections;
    const float unit = t_.unit_m;
    std::vector<std::vector<float>> arcs(particles_.size());
    for (size_t i = 0; i < particles_.size(); ++i) {
      const Particle& p = particles_[i];
      st.level.push_back(static_cast<uint8_t>(std::min(p.level, 255)));
      st.parent.push_back(p.parent);
      st.clone_of.push_back(-1);
      st.first_section.push_back(static_cast<uint32_t>(sec.size()));
      st.lobes.push_back(0);
      st.lobe_depth.push_back(0.0f);
      std::vector<float>& arc = arcs[i];
      float s = 0.0f;
      const size_t n = p.nodes.size();
      for (size_t k = 0; k <= n; ++k) {
        const Vec3 q = k < n ? p.nodes[k] : p.pos;
        const Vec3 dir = k == 0 ? p.start_dir : normalize_or(q - p.nodes[k - 1], p.start_dir);
        if (k > 0) s += glm::length(q - p.nodes[k - 1]) * unit;
        arc.push_back(s);
        const float width = k < n ? accumulated_width(p.growth, p.age, t_.iterations - p.node_born[k] + 1) : 0.0f;
        sec.positions.push_back(q * unit);
        sec.frames.push_back(Frame::from_z(dir));
        sec.radius_m.push_back(0.5f * width * unit);
        sec.arc_m.push_back(s);
      }
      st.section_count.push_back(static_cast<uint32_t>(n + 1));
      st.length_m.push_back(s);
      st.base_radius_m.push_back(sec.radius_m[st.first_section.back()]);
      float offset = 0.0f;
      if (p.parent >= 0) {
        const std::vector<float>& parc = arcs[static_cast<size_t>(p.parent)];
        offset = parc[std::min(p.parent_node, parc.size() - 1)];
      }
      st.offset_m.push_back(offset);
    }
  }

  // §II: "the program adds a leaf to the end of every branch ... in a random orientation limited by
  // the constraints in the template"; §IV, Figure 4: limb or leaf coordinates.
  void emit_leaves(TreeModel& m) const {
    if (t_.leaves.empty()) return;
    const std::vector<int> slot = element_slots();
    for (size_t i = 0; i < particles_.size(); ++i) {
      const Particle& p = particles_[i];
      Pcg32 rng(hash_ids(seed_, 0x1eafull, i));
      const float u = rng.uniform();
      size_t c = 0;
      float cumulative = t_.leaves[0].p;
      while (u >= cumulative && c + 1 < t_.leaves.size()) cumulative += t_.leaves[++c].p;
      const TreeMakerLeaf& leaf = t_.leaves[c];
      const Placement at{p.pos * t_.unit_m, leaf_frame(p, leaf, rng), t_.unit_m};
      for (const TreeMakerElement& e : leaf.elements) {
        const auto material = static_cast<uint8_t>(std::clamp(slot[static_cast<size_t>(e.color)], 0, 255));
        if (e.is_line())
          add_line(m, at, e.points[0], e.points[1], material, static_cast<int>(i));
        else
          add_triangle(m, at, e.points[0], e.points[1], e.points[2], material, static_cast<int>(i));
      }
    }
  }

  // The element frame: x across, y up, z out (§V: "The out vector ... is the z-axis"; "The up
  // vector, y-axis"). Deviations: the out axis turns about the up axis by up to ±out=, then the
  // whole frame tilts by up to up= about a random axis perpendicular to y.
  static Frame leaf_frame(const Particle& p, const TreeMakerLeaf& leaf, Pcg32& rng) {
    Vec3 y, z;
    if (leaf.coord == TreeMakerCoord::Limb) {
      z = p.dir;
      const Vec3 up = kUp - z * glm::dot(kUp, z);
      y = glm::length(up) > kVertical ? glm::normalize(up)
                                      : normalize_or(p.side - z * glm::dot(p.side, z), Frame::from_z(z).x);
    } else {
      y = kUp;
      const Vec3 h(p.dir.x, p.dir.y, 0.0f);
      z = glm::length(h) > kVertical ? glm::normalize(h) : p.side;
    }
    Vec3 x = glm::cross(y, z);
    const float turn = radians(rng.uniform(-leaf.out_deg, leaf.out_deg));
    z = rotate_vector(z, y, turn);
    x = rotate_vector(x, y, turn);
    const float beta = rng.uniform(0.0f, kTwoPi);
    const Vec3 axis = std::cos(beta) * x + std::sin(beta) * z;
    const float tilt = radians(rng.uniform(0.0f, leaf.up_deg));
    return Frame{rotate_vector(x, axis, tilt), rotate_vector(y, axis, tilt), rotate_vector(z, axis, tilt)};
  }

  void push_leaf(TreeModel& m, const Vec3& position, const Frame& f, float length, float width, LeafShape shape,
                 uint8_t material, int stem) const {
    TreeLeaves& l = m.leaves;
    if (l.size() >= kMaxTreeMakerLeaves)
      throw Error("tree too large: more than " + std::to_string(kMaxTreeMakerLeaves) +
                  " TREE-MAKER leaf quads (lower the branch numbers or the elements per leaf)");
    l.positions.push_back(position);
    l.frames.push_back(f);
    l.length_m.push_back(length);
    l.width_m.push_back(width);
    l.shapes.push_back(shape);
    l.stem.push_back(stem);
    l.material.push_back(material);
  }

  // A right triangle with the right angle at `corner` and legs a, b (leaf coordinates, template
  // units) as a RightTriangle quad whose upper side faces the element's +y.
  void add_right_triangle(TreeModel& m, const Placement& at, const Vec3& corner, Vec3 a, Vec3 b, uint8_t material,
                          int stem) const {
    if (!(glm::length(a) > 1e-6f) || !(glm::length(b) > 1e-6f)) return;
    if (glm::cross(a, b).y < 0.0f) std::swap(a, b);
    const Vec3 u = at.vector(a), v = at.vector(b);
    const float width = glm::length(u), length = glm::length(v);
    const Vec3 z = v / length;
    const Vec3 y = glm::cross(u / width, z);
    push_leaf(m, at.point(corner) + 0.5f * u, Frame{glm::cross(y, z), y, z}, length, width, LeafShape::RightTriangle,
              material, stem);
  }

  // tri=: one quad when the triangle has a right angle (the paper's petals do), otherwise split at
  // the foot of the altitude onto the longest edge (both angles there are acute, so the foot lies
  // on it) into two right triangles. Worked in the element's own coordinates, where it is exact.
  void add_triangle(TreeModel& m, const Placement& at, const Vec3& a, const Vec3& b, const Vec3& c, uint8_t material,
                    int stem) const {
    const Vec3 v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Vec3 e1 = v[(k + 1) % 3] - v[k], e2 = v[(k + 2) % 3] - v[k];
      if (std::abs(glm::dot(e1, e2)) <= 1e-6f * glm::length(e1) * glm::length(e2)) {
        add_right_triangle(m, at, v[k], e1, e2, material, stem);
        return;
      }
    }
    Vec3 p0 = a, p1 = b, q = c;
    const float ab = glm::length(b - a), bc = glm::length(c - b), ca = glm::length(a - c);
    if (bc >= ab && bc >= ca) {
      p0 = b, p1 = c, q = a;
    } else if (ca >= ab && ca >= bc) {
      p0 = c, p1 = a, q = b;
    }
    const Vec3 e = p1 - p0;
    const float l2 = glm::dot(e, e);
    if (!(l2 > 1e-12f)) return;
    const float t = std::clamp(glm::dot(q - p0, e) / l2, 0.0f, 1.0f);
    const Vec3 foot = p0 + t * e;
    const Vec3 h = q - foot;
    if (!(glm::length(h) > 1e-6f * std::sqrt(l2))) return;
    add_right_triangle(m, at, foot, p0 - foot, h, material, stem);
    add_right_triangle(m, at, foot, p1 - foot, h, material, stem);
  }

  // ln=: a ribbon line_width wide along the line, its face turned toward the element's +y.
  void add_line(TreeModel& m, const Placement& at, const Vec3& a, const Vec3& b, uint8_t material, int stem) const {
    const Vec3 d = b - a;
    const float l = glm::length(d);
    if (!(l > 1e-6f)) return;
    const Vec3 dz = d / l;
    const Vec3 facing = normalize_or(Vec3(0, 1, 0) - dz * dz.y, Frame::from_z(dz).x);
    const Vec3 z = at.f.to_world(dz), y = at.f.to_world(facing);
    push_leaf(m, at.point(a), Frame{glm::cross(y, z), y, z}, l * at.unit_m, t_.line_width * at.unit_m,
              LeafShape::Rectangle, material, stem);
  }

  std::vector<int> element_slots() const {
    std::vector<int> slot(t_.colors.size(), -1);
    int next = 0;
    for (const TreeMakerLeaf& leaf : t_.leaves)
      for (const TreeMakerElement& e : leaf.elements)
        if (slot[static_cast<size_t>(e.color)] < 0) slot[static_cast<size_t>(e.color)] = next++;
    return slot;
  }

  const TreeMakerTemplate& t_;
  uint64_t seed_;
  std::vector<Particle> particles_;
  size_t sections_ = 0;
};

}  // namespace

const TreeMakerBranchRule* TreeMakerTemplate::rule_for_level(int level) const {
  const TreeMakerBranchRule* best = nullptr;
  for (const TreeMakerBranchRule& r : branches)
    if (r.level <= level && (best == nullptr || r.level > best->level)) best = &r;
  return best;
}

TreeMakerMaterials treemaker_materials(const TreeMakerTemplate& tmpl) {
  validate(tmpl);
  TreeMakerMaterials out;
  std::vector<int> slot_of(tmpl.colors.size(), -1);
  std::vector<float> weight;
  for (const TreeMakerLeaf& leaf : tmpl.leaves)
    for (const TreeMakerElement& e : leaf.elements) {
      int& s = slot_of[static_cast<size_t>(e.color)];
      if (s < 0) {
        s = static_cast<int>(out.element_rgb.size());
        out.element_rgb.emplace_back(0.0f);
        out.element_color_names.push_back(tmpl.colors[static_cast<size_t>(e.color)].name);
        weight.push_back(0.0f);
      }
      const size_t k = static_cast<size_t>(s);
      out.element_rgb[k] +=
          normalised_rgb(tmpl.colors[static_cast<size_t>(e.color)].rgb) * (0.5f * (e.brightness.lo + e.brightness.hi));
      weight[k] += 1.0f;
    }
  for (size_t k = 0; k < out.element_rgb.size(); ++k) out.element_rgb[k] /= weight[k];
  for (const TreeMakerParticle& p : tmpl.particles)
    out.bark_rgb +=
        normalised_rgb(tmpl.colors[static_cast<size_t>(p.color)].rgb) * (0.5f * (p.brightness.lo + p.brightness.hi));
  if (!tmpl.particles.empty()) out.bark_rgb /= static_cast<float>(tmpl.particles.size());
  return out;
}

TreeModel make_treemaker_tree(const TreeMakerTemplate& tmpl, uint64_t seed) { return Grower(tmpl, seed).grow(); }

TreeModel make_tree(const TreeMakerTemplate& tmpl, uint64_t seed, const TreeOptions&) {
  return make_treemaker_tree(tmpl, seed);
}

TreeMakerTemplate TreeMakerTemplate::create(const Params& params, std::vector<std::string>&) {
  TreeMakerTemplate t;
  t.source = params.file_path("template");
  t.unit_m = params.real("unit_m", t.unit_m, 1e-6, 1e3);
  t.line_width = params.real("line_width", t.line_width, 0.0, 1e6);
  params.check_unused();
  return t;
}

}  // namespace sylva
