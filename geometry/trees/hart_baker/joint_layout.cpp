// Laying out a cluster of Hart–Baker joints: each limb followed out of the blends to the ring where
// the joint is cut from its tube (docs/hart_baker.md "Blended joints").

#include "geometry/trees/hart_baker/surface_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace sylva::surface_detail {

StemCone stem_cone(const TreeModel& model, size_t s) {
  const uint32_t a = model.stems.first_section[s];
  const uint32_t b = a + model.stems.section_count[s] - 1;
  StemCone c{{model.sections.positions[a], model.sections.positions[b], model.sections.radius_m[a],
              model.sections.radius_m[b]},
             {},
             {}};
  const float r = std::max(c.cone.base_radius_m, c.cone.tip_radius_m);
  c.lo = glm::min(c.cone.base, c.cone.tip) - Vec3(r);
  c.hi = glm::max(c.cone.base, c.cone.tip) + Vec3(r);
  return c;
}

// Children of every stem.
std::vector<std::vector<int32_t>> stem_children(const TreeModel& model) {
  std::vector<std::vector<int32_t>> children(model.stems.size());
  for (size_t s = 0; s < model.stems.size(); ++s)
    if (model.stems.parent[s] >= 0)
      children[static_cast<size_t>(model.stems.parent[s])].push_back(static_cast<int32_t>(s));
  return children;
}

namespace {

struct PathWalk {
  enum class End { Cut, Member, Other, Fails } end = End::Fails;
  int32_t met = -1;            // the joint met (Member, Other)
  std::vector<int32_t> stems;  // from the node outward; for a cut, the ring's stem last
  float ring_arc = 0;
  Vec3 ring{0.0f};
  Vec3 dir{0.0f};  // the axis at the ring, away from the node
  float radius = 0;
};

// Follows a limb away from a node — from `start`'s base toward its tip (up) or from its tip toward
// its base (down), on through yearly continuations — and places a ring `distance` metres out
// along the sections (on an existing section within `snap`), then looks on up to `ahead` metres
// further for another joint's node: one of the cluster's (`member`) makes the whole stretch inside
// the cluster (End::Member); another joint met before both joints' cuts (End::Other) has to join
// the cluster. Fails where the limb ends before the ring or turns into a lateral's base.
PathWalk walk_limb(const TreeModel& model, const std::vector<std::vector<int32_t>>& children,
                   const std::vector<int32_t>& joint_of, const std::vector<NodeJoint>& nodes,
                   const std::vector<uint8_t>& member, int32_t start, bool up, float distance, float ahead,
                   float snap) {
  PathWalk w;
  const StemSections& sec = model.sections;
  bool placed = false;
  size_t ring_stems = 0;
  float walked = 0;
  auto finish = [&]() {
    if (placed) {
      w.end = PathWalk::End::Cut;
      w.stems.resize(ring_stems);
    }
    return w;
  };
  int32_t s = start;
  while (true) {
    const size_t su = static_cast<size_t>(s);
    if (model.stems.is_dead(su)) return finish();
    w.stems.push_back(s);
    const uint32_t first = model.stems.first_section[su];
    const uint32_t count = model.stems.section_count[su];
    for (uint32_t k = 1; k < count; ++k) {
      const uint32_t a = up ? first + k - 1 : first + count - k;
      const uint32_t b = up ? a + 1 : a - 1;
      const float len = glm::length(sec.positions[b] - sec.positions[a]);
      if (!placed && walked + len >= distance && len > 0) {
        float t = (distance - walked) / len;
        if ((1 - t) * len < snap)
          t = 1;
        else if (t * len < snap && walked > 0)
          t = 0;
        w.ring_arc = t == 0 ? sec.arc_m[a] : t == 1 ? sec.arc_m[b] : sec.arc_m[a] + (sec.arc_m[b] - sec.arc_m[a]) * t;
        w.ring = sec.positions[a] + (sec.positions[b] - sec.positions[a]) * t;
        w.radius = sec.radius_m[a] + (sec.radius_m[b] - sec.radius_m[a]) * t;
        w.dir = (sec.positions[b] - sec.positions[a]) / len;
        if (w.radius <= 1e-6f) return w;
        placed = true;
        ring_stems = w.stems.size();
      }
      walked += len;
      if (placed && walked >= distance + ahead) return finish();
    }
    // The node at this end of the stem.
    const int32_t node = up ? s : model.stems.parent[su];
    if (node < 0) return finish();
    if (const int32_t j = joint_of[static_cast<size_t>(node)]; j >= 0) {
      const bool inside = member[static_cast<size_t>(j)] != 0;
      if (inside || walked < distance + nodes[static_cast<size_t>(j)].far) {
        w.end = inside ? PathWalk::End::Member : PathWalk::End::Other;
        w.met = j;
        return w;
      }
      return finish();
    }
    if (up) {
      int32_t next = -1;
      for (const int32_t c : children[su])
        if (!is_lateral(model, static_cast<size_t>(c))) next = c;
      if (next < 0) return finish();
      s = next;
    } else {
      if (is_lateral(model, su)) return finish();
      s = node;
    }
  }
}

// What layout_cluster reads: the model, its joints, the cluster's members and its cell.
struct Cluster {
  const std::vector<size_t>& members;
  const TreeModel& model;
  const std::vector<std::vector<int32_t>>& children;
  const std::vector<int32_t>& joint_of;
  const std::vector<NodeJoint>& nodes;
  const std::vector<StemCone>& cones;
  float ahead;
  float h;                      // the cluster's cell: its members' finest
  std::vector<uint8_t> member;  // per joint, whether it is one of the cluster's
};

// A limb at one of the cluster's nodes, followed out to its cut.
struct Limb {
  int32_t start;
  bool up;
  size_t node;
  float cut;
  PathWalk walk;
};

// Every limb at the cluster's nodes: the parent down, each child at least half a cell thick up.
// Empty when a node's thickest lateral is not among them.
std::optional<std::vector<Limb>> cluster_limbs(const Cluster& cl) {
  std::vector<Limb> limbs;
  for (const size_t j : cl.members) {
    const size_t p = static_cast<size_t>(cl.nodes[j].stem);
    limbs.push_back({cl.nodes[j].stem, false, j, 0.0f, {}});
    bool thickest = false;
    for (const int32_t c : cl.children[p]) {
      const float r = cl.cones[static_cast<size_t>(c)].cone.base_radius_m;
      if (r < 0.5f * cl.h) continue;  // drawn by its tube alone
      limbs.push_back({c, true, j, 0.0f, {}});
      thickest = thickest || (is_lateral(cl.model, static_cast<size_t>(c)) && r == cl.nodes[j].lateral);
    }
    if (!thickest) return std::nullopt;
  }
  return limbs;
}

// Whether limb i's cut (its ring, `gap` back toward the node) is clear: outside every blend and
// at least two cells from the other limbs.
bool cut_clear(const Cluster& cl, const std::vector<Limb>& limbs, size_t i, float gap) {
  const Limb& l = limbs[i];
  const Vec3 o = l.walk.ring - l.walk.dir * gap;
  const Frame f = Frame::from_z(l.walk.dir);
  bool clear = true;
  for (int k = 0; k < 16 && clear; ++k) {
    const float a = 2 * kPi * static_cast<float>(k) / 16;
    const Vec3 x = o + l.walk.radius * (std::cos(a) * f.x + std::sin(a) * f.y);
    for (const size_t j : cl.members)
      if (glm::length(x - cl.nodes[j].joint.centre) < cl.nodes[j].joint.reach_m) clear = false;
    for (size_t m = 0; m < limbs.size() && clear; ++m) {
      if (m == i) continue;
      for (const int32_t s : limbs[m].walk.stems) {
        if (std::find(l.walk.stems.begin(), l.walk.stems.end(), s) != l.walk.stems.end()) continue;
        const ConeDistance cd = cone_distance(x, cl.cones[static_cast<size_t>(s)].cone);
        if (cd.d - cd.r < 2 * cl.h) clear = false;
      }
    }
  }
  return clear;
}

// Walks every limb out to its cut, pushing a cut a cell further out while it is not clear: Ok,
// Join (another joint met, `out.join`) or Fails (a limb ends, or eight pushes do not clear them).
ClusterLayout::Result walk_to_cuts(const Cluster& cl, std::vector<Limb>& limbs, float gap, ClusterLayout& out) {
  using Result = ClusterLayout::Result;
  constexpr int kRounds = 8;
  for (int round = 0;; ++round) {
    for (Limb& l : limbs) {
      l.walk = walk_limb(cl.model, cl.children, cl.joint_of, cl.nodes, cl.member, l.start, l.up, l.cut + gap, cl.ahead,
                         0.25f * cl.h);
      if (l.walk.end == PathWalk::End::Fails) return Result::Fails;
      if (l.walk.end == PathWalk::End::Other) {
        out.join = l.walk.met;
        return Result::Join;
      }
    }
    bool moved = false;
    for (size_t i = 0; i < limbs.size(); ++i) {
      Limb& l = limbs[i];
      if (l.walk.end != PathWalk::End::Cut) continue;
      if (!cut_clear(cl, limbs, i, gap)) {
        l.cut += cl.h;
        moved = true;
      }
    }
    if (!moved) return Result::Ok;
    if (round == kRounds) return Result::Fails;
  }
}

// The stems the limbs run through (out.field) and those they run through whole (out.inside,
// flagged in `in_side`).
void limb_stems(const Cluster& cl, const std::vector<Limb>& limbs, ClusterLayout& out, std::vector<uint8_t>& in_side) {
  std::vector<uint8_t> in_field(cl.model.stems.size(), 0);
  in_side.assign(cl.model.stems.size(), 0);
  for (const Limb& l : limbs) {
    for (const int32_t s : l.walk.stems)
      if (!in_field[static_cast<size_t>(s)]++) out.field.push_back(s);
    const size_t whole = l.walk.stems.size() - (l.walk.end == PathWalk::End::Cut ? 1 : 0);
    for (size_t k = 0; k < whole; ++k)
      if (!in_side[static_cast<size_t>(l.walk.stems[k])]++) out.inside.push_back(l.walk.stems[k]);
  }
}

// The box holding the nodes' cubes and the limbs inside, two cells to spare.
void cluster_box(const Cluster& cl, ClusterLayout& out) {
  out.lo = Vec3(std::numeric_limits<float>::infinity());
  out.hi = -out.lo;
  for (const size_t j : cl.members) {
    out.lo = glm::min(out.lo, cl.nodes[j].joint.centre - Vec3(cl.nodes[j].half));
    out.hi = glm::max(out.hi, cl.nodes[j].joint.centre + Vec3(cl.nodes[j].half));
  }
  for (const int32_t s : out.inside) {
    out.lo = glm::min(out.lo, cl.cones[static_cast<size_t>(s)].lo - Vec3(2 * cl.h));
    out.hi = glm::max(out.hi, cl.cones[static_cast<size_t>(s)].hi + Vec3(2 * cl.h));
  }
}

// Each cut limb's JointCut, the box grown to hold its cylinder; false when a ring lies on a stem
// another limb runs through whole (it would be trimmed away).
bool add_cuts(const Cluster& cl, const std::vector<Limb>& limbs, const std::vector<uint8_t>& in_side, float gap,
              ClusterLayout& out) {
  for (const Limb& l : limbs) {
    if (l.walk.end != PathWalk::End::Cut) continue;
    if (in_side[static_cast<size_t>(l.walk.stems.back())]) return false;
    JointCut cut;
    cut.stem = l.walk.stems.back();
    cut.ring_arc_m = l.walk.ring_arc;
    cut.toward_tip = l.up;
    cut.origin = l.walk.ring - l.walk.dir * gap;
    cut.normal = l.walk.dir;
    cut.radius_m = 1.25f * l.walk.radius + cl.h;
    cut.gap_m = gap;
    // The box holds the cut's cylinder with two cells to spare.
    for (int a = 0; a < 3; ++a) {
      const float across = cut.radius_m * std::sqrt(std::max(0.0f, 1 - cut.normal[a] * cut.normal[a])) + 2 * cl.h;
      out.lo[a] = std::min(out.lo[a], cut.origin[a] - across);
      out.hi[a] = std::max(out.hi[a], cut.origin[a] + across);
    }
    out.cuts.push_back(std::move(cut));
  }
  return true;
}

}  // namespace

ClusterLayout layout_cluster(const std::vector<size_t>& members, const TreeModel& model,
                             const std::vector<std::vector<int32_t>>& children, const std::vector<int32_t>& joint_of,
                             const std::vector<NodeJoint>& nodes, const std::vector<StemCone>& cones, float ahead) {
  using Result = ClusterLayout::Result;
  Cluster cl{members,
             model,
             children,
             joint_of,
             nodes,
             cones,
             ahead,
             std::numeric_limits<float>::infinity(),
             std::vector<uint8_t>(nodes.size(), 0)};
  for (const size_t j : members) {
    cl.h = std::min(cl.h, nodes[j].cell);
    cl.member[j] = 1;
  }
  ClusterLayout out;
  std::optional<std::vector<Limb>> limbs = cluster_limbs(cl);
  if (!limbs) return out;
  const float gap = 1.5f * cl.h;
  for (Limb& l : *limbs) l.cut = nodes[l.node].joint.reach_m + 0.5f * cl.h;
  const Result walked = walk_to_cuts(cl, *limbs, gap, out);
  if (walked != Result::Ok) {
    out.result = walked;
    return out;
  }
  std::vector<uint8_t> in_side;
  limb_stems(cl, *limbs, out, in_side);
  if (out.field.size() > 16) return out;
  cluster_box(cl, out);
  if (!add_cuts(cl, *limbs, in_side, gap, out)) return out;
  out.cell = cl.h;
  out.result = Result::Ok;
  return out;
}

}  // namespace sylva::surface_detail
