// The Hart–Baker tree's blended joints (§5.2): one per node with a thick enough lateral, clustered
// where their limbs meet, polygonised, and opened at their cuts where they can be stitched to the
// tubes (docs/hart_baker.md "Blended joints").

#include "geometry/trees/hart_baker/surface_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sylva {

namespace surface_detail {
namespace {

// The cones near a node, the node's own limbs first (blended_cones reads at most 16): the field of
// a joint drawn closed over the tubes.
std::vector<BlendCone> cones_near(const TreeModel& model, const std::vector<StemCone>& cones,
                                  const std::vector<std::vector<int32_t>>& children, size_t p, const Vec3& centre,
                                  float half) {
  std::vector<BlendCone> nearby{cones[p].cone};
  for (const int32_t c : children[p]) nearby.push_back(cones[static_cast<size_t>(c)].cone);
  for (size_t s = 0; s < cones.size(); ++s) {
    if (s == p || model.stems.parent[s] == static_cast<int32_t>(p)) continue;
    const StemCone& c = cones[s];
    if (c.hi.x < centre.x - half || c.lo.x > centre.x + half || c.hi.y < centre.y - half || c.lo.y > centre.y + half ||
        c.hi.z < centre.z - half || c.lo.z > centre.z + half)
      continue;
    nearby.push_back(c.cone);
  }
  return nearby;
}

// The closed joint of one node, drawn over the tubes.
JointPlan closed_joint(const TreeModel& model, const std::vector<StemCone>& cones,
                       const std::vector<std::vector<int32_t>>& children, const NodeJoint& node) {
  JointPlan plan;
  plan.nodes = {node.stem};
  plan.joints = {node.joint};
  plan.lo = node.joint.centre - Vec3(node.half);
  plan.hi = node.joint.centre + Vec3(node.half);
  plan.cell_m = node.cell;
  plan.cones = cones_near(model, cones, children, static_cast<size_t>(node.stem), node.joint.centre, node.half);
  plan.mesh = polygonise_joint(plan.cones, node.joint, node.half, node.cells);
  return plan;
}

// Each of a stem's rings as the shared mesher makes it (make_tree_mesh): its axis — the stem's first
// frame at the first ring, then bisecting the pieces meeting there — and its reference direction,
// transported from ring to ring.
struct RingFrame {
  Vec3 axis;
  Vec3 ex;
};

std::vector<RingFrame> ring_frames(const TreeModel& model, size_t s) {
  auto safe_normalize = [](const Vec3& v, const Vec3& fallback) {
    const float l = glm::length(v);
    return l > 1e-12f ? v / l : fallback;
  };
  const StemSections& sec = model.sections;
  const uint32_t first = model.stems.first_section[s];
  const uint32_t count = model.stems.section_count[s];
  std::vector<RingFrame> rings(count);
  Vec3 ex = sec.frames[first].x;
  for (uint32_t k = 0; k < count; ++k) {
    Vec3 t = sec.frames[first].z;
    if (k > 0) {
      const Vec3 in = safe_normalize(sec.positions[first + k] - sec.positions[first + k - 1], sec.frames[first + k].z);
      t = in;
      if (k + 1 < count)
        t = safe_normalize(in + safe_normalize(sec.positions[first + k + 1] - sec.positions[first + k], in), in);
    }
    ex = safe_normalize(ex - t * glm::dot(ex, t), Frame::from_z(t).x);
    rings[k] = {t, ex};
  }
  return rings;
}

// Polygonises a laid-out cluster and opens it at its cuts; false when a cut is not clean or the
// box is too large. `ringed` is the model with the cuts' rings, as the tubes are meshed.
bool mesh_cluster(JointPlan& plan, const ClusterLayout& layout, const TreeModel& ringed,
                  const std::vector<StemCone>& cones, const TreeMeshOptions& options) {
  const glm::ivec3 cells = glm::ivec3(glm::ceil((layout.hi - layout.lo) / layout.cell));
  if (static_cast<double>(cells.x) * cells.y * cells.z > 8e6) return false;
  // Each limb as its tube's pieces, polygons as the shared mesher draws them, so that where the
  // joint is cut it is the tube's own surface (the sections also follow the reaction-wood
  // offsets, which a cone from base to tip does not).
  const StemSections& sec = ringed.sections;
  for (const int32_t s : layout.field) {
    const size_t su = static_cast<size_t>(s);
    const uint32_t first = ringed.stems.first_section[su];
    const uint32_t count = ringed.stems.section_count[su];
    const int sides = radial_segments_for_level(options, ringed.stems.level[su], ringed.stems.lobes[su]);
    const bool lobed = ringed.stems.lobes[su] > 0;
    const std::vector<RingFrame> rings = ring_frames(ringed, su);
    plan.cones.push_back(cones[su].cone);
    for (uint32_t k = 0; k + 1 < count; ++k) {
      TubePiece p;
      const uint32_t i = first + k;
      p.cone = {sec.positions[i], sec.positions[i + 1], sec.radius_m[i], sec.radius_m[i + 1]};
      p.base_axis = rings[k].axis;
      p.tip_axis = rings[k + 1].axis;
      const Vec3 along = sec.positions[i + 1] - sec.positions[i];
      const float len = glm::length(along);
      const bool pointed = k + 2 == count && sec.radius_m[i + 1] <= 1e-7f;
      if (len > 0 && !lobed && !pointed) {
        const Vec3 u = along / len;
        const Vec3 ex = rings[k].ex - u * glm::dot(rings[k].ex, u);
        if (glm::length(ex) > 1e-6f) {
          p.ex = glm::normalize(ex);
          p.ey = glm::cross(u, p.ex);
          p.sides = sides;
          p.rounding_m = layout.cell;
        }
      }
      plan.pieces.push_back(p);
    }
  }
  const std::vector<PieceBall> balls = piece_balls(plan.pieces);
  auto field = [&](const Vec3& x) { return plan_field(x, plan.cones, plan.pieces, balls, plan.joints, false); };
  auto round = [&](const Vec3& x) { return plan_field(x, plan.cones, plan.pieces, balls, plan.joints, true); };
  TriangleMesh mesh = polygonise_box(FieldRef(field), FieldRef(round), layout.lo, cells, layout.cell, plan.joints);
  std::vector<JointCut> cuts = layout.cuts;
  for (JointCut& c : cuts)
    if (!open_joint(mesh, c, FieldRef(field), FieldRef(round), layout.cell)) return false;
  plan.lo = layout.lo;
  plan.hi = layout.lo + Vec3(cells) * layout.cell;
  plan.cell_m = layout.cell;
  plan.cuts = std::move(cuts);
  plan.inside = layout.inside;
  plan.mesh = std::move(mesh);
  plan.stitched = true;
  return true;
}

// The model with a section at every cut's ring, on the straight piece of the stem that holds it.
TreeModel with_rings(const TreeModel& model, const std::vector<JointCut>& cuts) {
  if (cuts.empty()) return model;
  std::vector<std::vector<float>> rings(model.stems.size());
  for (const JointCut& c : cuts) rings[static_cast<size_t>(c.stem)].push_back(c.ring_arc_m);
  TreeModel out = model;
  const StemSections& in = model.sections;
  StemSections& sec = out.sections;
  sec = {};
  for (size_t s = 0; s < model.stems.size(); ++s) {
    std::vector<float>& add = rings[s];
    std::sort(add.begin(), add.end());
    const uint32_t first = model.stems.first_section[s];
    const uint32_t count = model.stems.section_count[s];
    out.stems.first_section[s] = static_cast<uint32_t>(sec.size());
    size_t next = 0;
    for (uint32_t k = 0; k < count; ++k) {
      const uint32_t i = first + k;
      // Rings strictly inside the piece ending at section i, on its straight line.
      while (k > 0 && next < add.size() && add[next] < in.arc_m[i]) {
        if (add[next] > in.arc_m[i - 1]) {
          const float t = (add[next] - in.arc_m[i - 1]) / (in.arc_m[i] - in.arc_m[i - 1]);
          sec.positions.push_back(in.positions[i - 1] + (in.positions[i] - in.positions[i - 1]) * t);
          sec.frames.push_back(in.frames[i]);
          sec.radius_m.push_back(in.radius_m[i - 1] + (in.radius_m[i] - in.radius_m[i - 1]) * t);
          sec.arc_m.push_back(add[next]);
        }
        ++next;
      }
      sec.positions.push_back(in.positions[i]);
      sec.frames.push_back(in.frames[i]);
      sec.radius_m.push_back(in.radius_m[i]);
      sec.arc_m.push_back(in.arc_m[i]);
    }
    out.stems.section_count[s] = static_cast<uint32_t>(sec.size()) - out.stems.first_section[s];
  }
  return out;
}

// The joints' nodes: every stem whose thickest lateral is at least joint_min_radius_m thick, its
// blend (centre at the parent's tip, reach and fillet from the surface's factors) and closed cube.
// `joint_of` gets each stem's joint (−1: none), `ahead` the furthest any joint's limbs are cut.
std::vector<NodeJoint> node_joints(const TreeModel& model, const HartBakerSurface& surface,
                                   const std::vector<StemCone>& cones,
                                   const std::vector<std::vector<int32_t>>& children, std::vector<int32_t>& joint_of,
                                   float& ahead) {
  std::vector<NodeJoint> nodes;
  for (size_t p = 0; p < cones.size(); ++p) {
    float lateral = 0;
    for (const int32_t c : children[p])
      if (is_lateral(model, static_cast<size_t>(c)))
        lateral = std::max(lateral, cones[static_cast<size_t>(c)].cone.base_radius_m);
    if (lateral <= 0 || lateral < surface.joint_min_radius_m) continue;
    const BlendCone& parent = cones[p].cone;
    const float parent_r = parent.tip_radius_m;
    NodeJoint n{};
    n.stem = static_cast<int32_t>(p);
    n.joint = {parent.tip, surface.reach * std::max(parent_r, lateral), surface.fillet * lateral};
    n.half = n.joint.reach_m * 1.1f;
    // Cells small enough that the thinnest limb at the node is several cells across.
    float thinnest = parent_r;
    for (const int32_t c : children[p]) thinnest = std::min(thinnest, cones[static_cast<size_t>(c)].cone.base_radius_m);
    n.cells = std::clamp(static_cast<int>(std::ceil(2 * n.half / (0.5f * thinnest))), 8, surface.joint_cells);
    n.cell = 2 * n.half / static_cast<float>(n.cells);
    n.lateral = lateral;
    n.far = n.joint.reach_m + 2 * n.cell;
    ahead = std::max(ahead, n.far);
    joint_of[p] = static_cast<int32_t>(nodes.size());
    nodes.push_back(n);
  }
  return nodes;
}

// Union–find over the joints, the least index the root.
struct JointSets {
  std::vector<size_t> root;

  explicit JointSets(size_t n) : root(n) {
    for (size_t j = 0; j < n; ++j) root[j] = j;
  }
  size_t find(size_t j) {
    while (root[j] != j) j = root[j] = root[root[j]];
    return j;
  }
  void unite(size_t a, size_t b) {
    a = find(a), b = find(b);
    if (a != b) root[std::max(a, b)] = std::min(a, b);
  }
};

// Unites the clusters whose layouts trim the same stretch of a tube; whether any were.
bool unite_overlapping_trims(const std::vector<ClusterLayout>& layouts, size_t stems, JointSets& sets) {
  struct Trim {
    size_t cluster;
    float lo, hi;
  };
  std::vector<std::vector<Trim>> trims(stems);
  constexpr float kAll = std::numeric_limits<float>::infinity();
  for (size_t c = 0; c < layouts.size(); ++c) {
    if (layouts[c].result != ClusterLayout::Result::Ok) continue;
    for (const int32_t s : layouts[c].inside) trims[static_cast<size_t>(s)].push_back({c, -kAll, kAll});
    for (const JointCut& cut : layouts[c].cuts)
      trims[static_cast<size_t>(cut.stem)].push_back(
          {c, cut.toward_tip ? -kAll : cut.ring_arc_m, cut.toward_tip ? cut.ring_arc_m : kAll});
  }
  bool changed = false;
  for (const std::vector<Trim>& on : trims)
    for (size_t a = 0; a < on.size(); ++a)
      for (size_t b = a + 1; b < on.size(); ++b)
        if (on[a].cluster != on[b].cluster && on[a].lo <= on[b].hi && on[b].lo <= on[a].hi) {
          sets.unite(on[a].cluster, on[b].cluster);
          changed = true;
        }
  return changed;
}

// The joints' clusters (members by root) and their layouts.
struct Clusters {
  std::vector<std::vector<size_t>> members;
  std::vector<ClusterLayout> layouts;
};

// Clusters the joints: those whose limbs meet before both are cut, or whose trims would overlap,
// are laid out together, until no layout asks for another joint and no trims overlap.
Clusters cluster_joints(const TreeModel& model, const std::vector<std::vector<int32_t>>& children,
                        const std::vector<int32_t>& joint_of, const std::vector<NodeJoint>& nodes,
                        const std::vector<StemCone>& cones, float ahead) {
  JointSets sets(nodes.size());
  constexpr size_t kMostJoints = 8;
  Clusters out;
  for (bool changed = true; changed;) {
    changed = false;
    out.members.assign(nodes.size(), {});
    for (size_t j = 0; j < nodes.size(); ++j) out.members[sets.find(j)].push_back(j);
    out.layouts.assign(nodes.size(), ClusterLayout{});
    for (size_t c = 0; c < nodes.size(); ++c) {
      if (out.members[c].empty() || out.members[c].size() > kMostJoints) continue;
      out.layouts[c] = layout_cluster(out.members[c], model, children, joint_of, nodes, cones, ahead);
      if (out.layouts[c].result == ClusterLayout::Result::Join) {
        sets.unite(c, static_cast<size_t>(out.layouts[c].join));
        changed = true;
      }
    }
    if (changed) continue;
    // Two clusters may not trim the same stretch of a tube.
    changed = unite_overlapping_trims(out.layouts, cones.size(), sets);
  }
  return out;
}

}  // namespace
}  // namespace surface_detail

HartBakerJoints plan_hart_baker_joints(const TreeModel& model, const HartBakerSurface& surface,
                                       const TreeMeshOptions& options) {
  using namespace surface_detail;  // the internals (surface_detail.h)
  const size_t count = model.stems.size();
  std::vector<StemCone> cones(count);
  for (size_t s = 0; s < count; ++s) cones[s] = stem_cone(model, s);
  const std::vector<std::vector<int32_t>> children = stem_children(model);
  std::vector<int32_t> joint_of(count, -1);
  float ahead = 0;
  const std::vector<NodeJoint> nodes = node_joints(model, surface, cones, children, joint_of, ahead);
  const Clusters clusters = cluster_joints(model, children, joint_of, nodes, cones, ahead);
  const std::vector<std::vector<size_t>>& members = clusters.members;
  const std::vector<ClusterLayout>& layouts = clusters.layouts;
  // The tubes get their rings before the clusters are polygonised: a cluster's pieces are the
  // tubes' own, rings included.
  std::vector<JointCut> cuts;
  for (size_t c = 0; c < nodes.size(); ++c)
    if (layouts[c].result == ClusterLayout::Result::Ok)
      cuts.insert(cuts.end(), layouts[c].cuts.begin(), layouts[c].cuts.end());
  HartBakerJoints out{with_rings(model, cuts), {}};
  for (size_t c = 0; c < nodes.size(); ++c) {
    if (members[c].empty()) continue;
    if (layouts[c].result == ClusterLayout::Result::Ok) {
      JointPlan plan;
      for (const size_t j : members[c]) {
        plan.nodes.push_back(nodes[j].stem);
        plan.joints.push_back(nodes[j].joint);
      }
      if (mesh_cluster(plan, layouts[c], out.ringed, cones, options)) {
        out.plans.push_back(std::move(plan));
        continue;
      }
    }
    for (const size_t j : members[c]) out.plans.push_back(closed_joint(model, cones, children, nodes[j]));
  }
  return out;
}

}  // namespace sylva
