// Laying out a cluster of Hart–Baker joints: each limb followed out of the blends to the ring where
// the joint is cut from its tube (docs/hart_baker.md "Blended joints").

#include "geometry/trees/hart_baker/surface_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

}  // namespace

ClusterLayout layout_cluster(const std::vector<size_t>& members, const TreeModel& model,
                             const std::vector<std::vector<int32_t>>& children, const std::vector<int32_t>& joint_of,
                             const std::vector<NodeJoint>& nodes, const std::vector<StemCone>& cones, float ahead) {
  using Result = ClusterLayout::Result;
  ClusterLayout out;
  float h = std::numeric_limits<float>::infinity();
  std::vector<uint8_t> member(nodes.size(), 0);
  for (const size_t j : members) {
    h = std::min(h, nodes[j].cell);
    member[j] = 1;
  }
  struct Limb {
    int32_t start;
    bool up;
    size_t node;
    float cut;
    PathWalk walk;
  };
  std::vector<Limb> limbs;
  for (const size_t j : members) {
    const size_t p = static_cast<size_t>(nodes[j].stem);
    limbs.push_back({nodes[j].stem, false, j, 0.0f, {}});
    bool thickest = false;
    for (const int32_t c : children[p]) {
      const float r = cones[static_cast<size_t>(c)].cone.base_radius_m;
      if (r < 0.5f * h) continue;  // drawn by its tube alone
      limbs.push_back({c, true, j, 0.0f, {}});
      thickest = thickest || (is_lateral(model, static_cast<size_t>(c)) && r == nodes[j].lateral);
    }
    if (!thickest) return out;
  }
  const float gap = 1.5f * h;
  for (Limb& l : limbs) l.cut = nodes[l.node].joint.reach_m + 0.5f * h;
  constexpr int kRounds = 8;
  for (int round = 0;; ++round) {
    for (Limb& l : limbs) {
      l.walk = walk_limb(model, children, joint_of, nodes, member, l.start, l.up, l.cut + gap, ahead, 0.25f * h);
      if (l.walk.end == PathWalk::End::Fails) return out;
      if (l.walk.end == PathWalk::End::Other) {
        out.result = Result::Join;
        out.join = l.walk.met;
        return out;
      }
    }
    // Push a cut out while its ring is in a blend or within two cells of another limb.
    bool moved = false;
    for (size_t i = 0; i < limbs.size(); ++i) {
      Limb& l = limbs[i];
      if (l.walk.end != PathWalk::End::Cut) continue;
      const Vec3 o = l.walk.ring - l.walk.dir * gap;
      const Frame f = Frame::from_z(l.walk.dir);
      bool clear = true;
      for (int k = 0; k < 16 && clear; ++k) {
        const float a = 2 * kPi * static_cast<float>(k) / 16;
        const Vec3 x = o + l.walk.radius * (std::cos(a) * f.x + std::sin(a) * f.y);
        for (const size_t j : members)
          if (glm::length(x - nodes[j].joint.centre) < nodes[j].joint.reach_m) clear = false;
        for (size_t m = 0; m < limbs.size() && clear; ++m) {
          if (m == i) continue;
          for (const int32_t s : limbs[m].walk.stems) {
            if (std::find(l.walk.stems.begin(), l.walk.stems.end(), s) != l.walk.stems.end()) continue;
            const ConeDistance cd = cone_distance(x, cones[static_cast<size_t>(s)].cone);
            if (cd.d - cd.r < 2 * h) clear = false;
          }
        }
      }
      if (!clear) {
        l.cut += h;
        moved = true;
      }
    }
    if (!moved) break;
    if (round == kRounds) return out;
  }
  std::vector<uint8_t> in_field(model.stems.size(), 0), in_side(model.stems.size(), 0);
  for (const Limb& l : limbs) {
    for (const int32_t s : l.walk.stems)
      if (!in_field[static_cast<size_t>(s)]++) out.field.push_back(s);
    const size_t whole = l.walk.stems.size() - (l.walk.end == PathWalk::End::Cut ? 1 : 0);
    for (size_t k = 0; k < whole; ++k)
      if (!in_side[static_cast<size_t>(l.walk.stems[k])]++) out.inside.push_back(l.walk.stems[k]);
  }
  if (out.field.size() > 16) return out;
  out.lo = Vec3(std::numeric_limits<float>::infinity());
  out.hi = -out.lo;
  for (const size_t j : members) {
    out.lo = glm::min(out.lo, nodes[j].joint.centre - Vec3(nodes[j].half));
    out.hi = glm::max(out.hi, nodes[j].joint.centre + Vec3(nodes[j].half));
  }
  for (const int32_t s : out.inside) {
    out.lo = glm::min(out.lo, cones[static_cast<size_t>(s)].lo - Vec3(2 * h));
    out.hi = glm::max(out.hi, cones[static_cast<size_t>(s)].hi + Vec3(2 * h));
  }
  for (const Limb& l : limbs) {
    if (l.walk.end != PathWalk::End::Cut) continue;
    // A ring on a stem another limb runs through whole would be trimmed away.
    if (in_side[static_cast<size_t>(l.walk.stems.back())]) return out;
    JointCut cut;
    cut.stem = l.walk.stems.back();
    cut.ring_arc_m = l.walk.ring_arc;
    cut.toward_tip = l.up;
    cut.origin = l.walk.ring - l.walk.dir * gap;
    cut.normal = l.walk.dir;
    cut.radius_m = 1.25f * l.walk.radius + h;
    cut.gap_m = gap;
    // The box holds the cut's cylinder with two cells to spare.
    for (int a = 0; a < 3; ++a) {
      const float across = cut.radius_m * std::sqrt(std::max(0.0f, 1 - cut.normal[a] * cut.normal[a])) + 2 * h;
      out.lo[a] = std::min(out.lo[a], cut.origin[a] - across);
      out.hi[a] = std::max(out.hi[a], cut.origin[a] + across);
    }
    out.cuts.push_back(std::move(cut));
  }
  out.cell = h;
  out.result = Result::Ok;
  return out;
}

}  // namespace sylva::surface_detail
