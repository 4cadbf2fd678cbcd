// Hart–Baker bark (§5.4): spotted or ribbon relief placed along the particle flow (bark_flow.cpp).

#include "geometry/trees/hart_baker/surface_detail.h"

#include "core/hash.h"
#include "core/rng.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace sylva {

namespace surface_detail {
namespace {

// Where a stitched joint is the surface: in its box and short of every cut.
bool in_stitched(const JointPlan& plan, const Vec3& p) {
  if (!plan.stitched || glm::any(glm::lessThan(p, plan.lo)) || glm::any(glm::greaterThan(p, plan.hi))) return false;
  for (const JointCut& c : plan.cuts) {
    const Vec3 rel = p - c.origin;
    const float along = glm::dot(rel, c.normal);
    if (along > 0 && glm::length(rel - c.normal * along) < c.radius_m) return false;
  }
  return true;
}

// How far along n from p a stitched joint's surface lies (within reach either way), if it does.
std::optional<float> to_joint_surface(const JointPlan& plan, const Vec3& p, const Vec3& n, float reach) {
  float lo = -reach, hi = reach;
  float flo = joint_plan_field(plan, p + n * lo), fhi = joint_plan_field(plan, p + n * hi);
  if (flo >= 0 || fhi <= 0) return std::nullopt;
  for (int it = 0; it < 30; ++it) {
    const float mid = 0.5f * (lo + hi);
    if (joint_plan_field(plan, p + n * mid) < 0)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5f * (lo + hi);
}

// What the bark's features are placed on: the limbs as cones, their children, and the joints.
struct BarkLimbs {
  const TreeModel& model;
  const HartBakerBark& bark;
  std::span<const JointPlan> joints;
  std::vector<BlendCone> cones;
  std::vector<std::vector<int32_t>> children;
};

// Whether x lies within a feature's size of stem `other`'s cone.
bool inside_one(const BarkLimbs& limbs, int32_t other, const Vec3& x) {
  const ConeDistance cd = cone_distance(x, limbs.cones[static_cast<size_t>(other)]);
  return cd.d - cd.r < limbs.bark.size_m;
}

// Whether x, on stem s, lies where the limb runs inside its neighbours at a node (a lateral's
// base inside the parent or its continuation, a parent's tip inside its children).
bool inside_neighbour(const BarkLimbs& limbs, size_t s, const Vec3& x) {
  const int32_t parent = limbs.model.stems.parent[s];
  if (parent >= 0) {
    if (inside_one(limbs, parent, x)) return true;
    for (const int32_t sibling : limbs.children[static_cast<size_t>(parent)])
      if (static_cast<size_t>(sibling) != s && inside_one(limbs, sibling, x)) return true;
  }
  for (const int32_t child : limbs.children[s])
    if (inside_one(limbs, child, x)) return true;
  return false;
}

// How far along n a feature at `at` moves onto a stitched joint's surface (0 where no stitched
// joint is the surface); empty when the joint's surface is not within reach.
std::optional<float> onto_joints(std::span<const JointPlan> joints, const Vec3& at, const Vec3& n) {
  for (const JointPlan& plan : joints)
    if (in_stitched(plan, at)) {
      float fillet = 0;
      for (const BlendJoint& j : plan.joints) fillet = std::max(fillet, j.fillet_m);
      const std::optional<float> d = to_joint_surface(plan, at, n, fillet + plan.cell_m);
      if (!d) return std::nullopt;
      return d.value_or(0.0f);
    }
  return 0.0f;
}

// Where a feature sits: its anchor on the limb, the limb's outward normal, axis and the direction
// across it there, and how far it moves onto a joint.
struct BarkSite {
  Vec3 at, n, along, across;
  float onto;
};

// The feature of flow line l's point i, drawing its density and jitter from `rng`; empty where
// none is placed.
std::optional<BarkSite> bark_site(const BarkLimbs& limbs, const BarkFlow& flow, size_t l, size_t i, Pcg32& rng) {
  const HartBakerBark& bark = limbs.bark;
  const std::vector<Vec3>& line = flow.lines[l];
  const size_t s = static_cast<size_t>(flow.stems[l][i]);
  if (flow.stems[l][i + 1] != flow.stems[l][i]) return std::nullopt;
  const BlendCone& c = limbs.cones[s];
  if (c.base_radius_m < bark.min_radius_m) return std::nullopt;
  if (rng.uniform() >= bark.density) return std::nullopt;
  const Vec3 along = glm::normalize(c.tip - c.base);
  const Vec3 p = line[i];
  const Vec3 to_axis = p - (c.base + along * glm::dot(p - c.base, along));
  if (glm::length(to_axis) <= 0) return std::nullopt;
  const Vec3 n = glm::normalize(to_axis);
  const Vec3 across = glm::cross(along, n);
  // Jitter along the line so features do not line up in rows.
  Vec3 at = p + along * (bark.spacing_m * (rng.uniform() - 0.5f));
  // The whole feature on this limb.
  const float extent = 0.5f * (bark.kind == BarkKind::Ribbon ? 1.3f * bark.length_m : 1.4f * bark.size_m * bark.aspect);
  const float limb_length = glm::length(c.tip - c.base);
  if (limb_length < 2 * extent) return std::nullopt;
  at += along * (std::clamp(glm::dot(at - c.base, along), extent, limb_length - extent) - glm::dot(at - c.base, along));
  if (inside_neighbour(limbs, s, at)) return std::nullopt;
  // Where a stitched joint is the surface, onto it.
  const std::optional<float> onto = onto_joints(limbs.joints, at, n);
  if (!onto) return std::nullopt;
  return BarkSite{at, n, along, across, *onto};
}

// Adds a vertex at p with normal n; its index.
uint32_t add_vertex(TriangleMesh& mesh, const Vec3& p, const Vec3& n) {
  mesh.positions.push_back(p);
  mesh.normals.push_back(n);
  mesh.uvs.emplace_back(0.0f, 0.0f);
  return static_cast<uint32_t>(mesh.positions.size() - 1);
}

// A spot (§5.4): a fan of triangles, its rim `lift` off the bark of cone c and its peak height_m
// above it.
void add_spot(TriangleMesh& mesh, const HartBakerBark& bark, const BlendCone& c, const BarkSite& site, float lift,
              Pcg32& rng) {
  const Vec3 &at = site.at, &n = site.n, &along = site.along, &across = site.across;
  const float w = bark.size_m * (0.6f + 0.8f * rng.uniform()) * 0.5f;
  const float hgt = w * bark.aspect;
  const uint32_t peak = add_vertex(mesh, at + n * bark.height_m, n);
  constexpr int kRim = 8;
  const uint32_t first = static_cast<uint32_t>(mesh.positions.size());
  for (int k = 0; k < kRim; ++k) {
    const float a = 2 * kPi * static_cast<float>(k) / kRim;
    const Vec3 q = at + across * (w * std::cos(a)) + along * (hgt * std::sin(a));
    const Vec3 q_axis = c.base + along * glm::dot(q - c.base, along);
    const float t = std::clamp(glm::dot(q - c.base, along) / glm::length(c.tip - c.base), 0.0f, 1.0f);
    const float r = (1 - t) * c.base_radius_m + t * c.tip_radius_m;
    const Vec3 out = glm::normalize(q - q_axis);
    add_vertex(mesh, q_axis + out * (r + lift), out);
  }
  for (int k = 0; k < kRim; ++k)
    mesh.triangles.emplace_back(peak, first + static_cast<uint32_t>(k), first + static_cast<uint32_t>((k + 1) % kRim));
}

// A ribbon (§5.4): a segmented strip along the grain of cone c, turned by a random twist, its
// ridge height_m above the bark and its edges `lift` off it.
void add_ribbon(TriangleMesh& mesh, const HartBakerBark& bark, const BlendCone& c, const BarkSite& site, float lift,
                Pcg32& rng) {
  const Vec3 &at = site.at, &n = site.n, &along = site.along, &across = site.across;
  const float turn = bark.twist_deg * kPi / 180 * (2 * rng.uniform() - 1);
  const Vec3 dir = along * std::cos(turn) + across * std::sin(turn);
  const Vec3 side = glm::cross(dir, n);
  const float len = bark.length_m * (0.7f + 0.6f * rng.uniform());
  const float w = bark.size_m * 0.5f;
  constexpr int kSegments = 4;
  const uint32_t first = static_cast<uint32_t>(mesh.positions.size());
  for (int k = 0; k <= kSegments; ++k) {
    const float v = (static_cast<float>(k) / kSegments - 0.5f) * len;
    const Vec3 q = at + dir * v;
    const float t = std::clamp(glm::dot(q - c.base, along) / glm::length(c.tip - c.base), 0.0f, 1.0f);
    const float r = (1 - t) * c.base_radius_m + t * c.tip_radius_m;
    const Vec3 q_axis = c.base + along * glm::dot(q - c.base, along);
    for (int e = -1; e <= 1; ++e) {
      const Vec3 o = q + side * (w * static_cast<float>(e));
      const Vec3 o_axis = c.base + along * glm::dot(o - c.base, along);
      const Vec3 out = glm::normalize(o - o_axis);
      const float rise = e == 0 ? bark.height_m : lift;
      add_vertex(mesh, (e == 0 ? q_axis + glm::normalize(q - q_axis) * r : o_axis + out * r) + out * rise,
                 glm::normalize(out + side * (-0.5f * static_cast<float>(e))));
    }
  }
  for (int k = 0; k < kSegments; ++k) {
    const uint32_t a = first + static_cast<uint32_t>(3 * k), b = a + 3;
    mesh.triangles.emplace_back(a, a + 1, b + 1);
    mesh.triangles.emplace_back(a, b + 1, b);
    mesh.triangles.emplace_back(a + 1, a + 2, b + 2);
    mesh.triangles.emplace_back(a + 1, b + 2, b + 1);
  }
}

// Faces every triangle outward (along its vertices' normals).
void face_outward(TriangleMesh& mesh) {
  for (glm::uvec3& t : mesh.triangles) {
    const Vec3 nrm = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
    if (glm::dot(nrm, mesh.normals[t.x] + mesh.normals[t.y] + mesh.normals[t.z]) < 0) std::swap(t.y, t.z);
  }
}

}  // namespace
}  // namespace surface_detail

TriangleMesh hart_baker_bark(const TreeModel& model, const HartBakerParams& params, std::span<const JointPlan> joints) {
  using namespace surface_detail;  // the internals (surface_detail.h)
  const HartBakerBark& bark = params.bark;
  TriangleMesh mesh;
  if (bark.kind == BarkKind::Smooth) return mesh;
  const BarkFlow flow = hart_baker_bark_flow(model, params);
  BarkLimbs limbs{model, bark, joints, std::vector<BlendCone>(model.stems.size()), stem_children(model)};
  for (size_t s = 0; s < limbs.cones.size(); ++s) limbs.cones[s] = stem_cone(model, s).cone;
  const float lift = 0.05f * bark.height_m + 1e-4f;  // feature edges stand just off the tube
  for (size_t l = 0; l < flow.lines.size(); ++l)
    for (size_t i = 0; i + 1 < flow.lines[l].size(); ++i) {
      Pcg32 rng(hash_ids(0xba4cu, l, i));
      const std::optional<BarkSite> site = bark_site(limbs, flow, l, i, rng);
      if (!site) continue;
      const BlendCone& c = limbs.cones[static_cast<size_t>(flow.stems[l][i])];
      const auto feature = static_cast<uint32_t>(mesh.positions.size());
      if (bark.kind == BarkKind::Spotted)
        add_spot(mesh, bark, c, *site, lift, rng);
      else
        add_ribbon(mesh, bark, c, *site, lift, rng);
      for (uint32_t v = feature; v < mesh.positions.size(); ++v) mesh.positions[v] += site->n * site->onto;
    }
  face_outward(mesh);
  return mesh;
}

}  // namespace sylva
