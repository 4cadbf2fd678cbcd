// Hart–Baker bark: the particle flow over the limbs (§5.3) and spotted or ribbon relief placed
// along it (§5.4).

#include "geometry/trees/hart_baker/surface_detail.h"

#include "core/hash.h"
#include "core/rng.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace sylva {

using namespace surface_detail;

namespace {

// Keeps a ring of particle angles between the chain's link lengths (§5.3: maximum 3× minimum):
// splits the widest gaps while a link is too long, merges the narrowest while one is too short.
void respace(std::vector<float>& angles, float circumference, float spacing) {
  std::sort(angles.begin(), angles.end());
  const float max_link = 1.5f * spacing, min_link = 0.5f * spacing;
  const size_t least = std::max<size_t>(3, static_cast<size_t>(std::ceil(circumference / max_link)));
  const size_t most = std::max<size_t>(least, static_cast<size_t>(std::floor(circumference / min_link)));
  if (angles.empty()) angles.push_back(0.0f);
  auto gap = [&](size_t i) {
    const float next = i + 1 < angles.size() ? angles[i + 1] : angles[0] + 2 * kPi;
    return next - angles[i];
  };
  while (angles.size() < least) {
    size_t widest = 0;
    for (size_t i = 1; i < angles.size(); ++i)
      if (gap(i) > gap(widest)) widest = i;
    angles.insert(angles.begin() + static_cast<ptrdiff_t>(widest) + 1, wrap(angles[widest] + gap(widest) / 2));
    std::sort(angles.begin(), angles.end());
  }
  while (angles.size() > most) {
    size_t narrowest = 0;
    for (size_t i = 1; i < angles.size(); ++i)
      if (gap(i) < gap(narrowest)) narrowest = i;
    angles.erase(angles.begin() + static_cast<ptrdiff_t>(narrowest));
  }
}

}  // namespace

BarkFlow hart_baker_bark_flow(const TreeModel& model, const HartBakerParams& params) {
  // §5.3's chain of particles, advanced along each limb and split at every node. A particle keeps
  // its angle about the limb (its momentum carries it straight up the grain); at a node the ring of particles divides
  // as Table 2's relinking divides the chain: each lateral takes the arc of the ring facing it, in proportion to its
  // share of the node's circumferences, closed into a loop around the lateral; the continuation takes the rest. The
  // springs' minimum and maximum link lengths become respace().
  const HartBakerBark& bark = params.bark;
  const size_t count = model.stems.size();
  BarkFlow flow;
  if (count == 0) return flow;
  const std::vector<std::vector<int32_t>> children = stem_children(model);
  std::vector<std::vector<float>> angles(count);
  std::vector<std::vector<int32_t>> line_of(count);  // the flow line each particle extends
  std::vector<Frame> frames(count);
  std::vector<BlendCone> cones(count);
  for (size_t s = 0; s < count; ++s) {
    cones[s] = stem_cone(model, s).cone;
    const Vec3 axis = cones[s].tip - cones[s].base;
    frames[s] = Frame::from_z(glm::length(axis) > 0 ? glm::normalize(axis) : Vec3(0, 0, 1));
  }
  // Roots: every stem without a parent starts a ring at its base.
  for (size_t s = 0; s < count; ++s) {
    if (model.stems.parent[s] >= 0) continue;
    respace(angles[s], 2 * kPi * cones[s].base_radius_m, bark.spacing_m);
    line_of[s].clear();
    for (size_t k = 0; k < angles[s].size(); ++k) line_of[s].push_back(-1);
  }
  for (size_t s = 0; s < count; ++s) {
    const BlendCone& c = cones[s];
    const Frame& f = frames[s];
    // Advance the ring up the limb, one step per spacing; the grain runs straight along a cone.
    const float length = glm::length(c.tip - c.base);
    const int steps = std::max(1, static_cast<int>(std::ceil(length / bark.spacing_m)));
    for (size_t k = 0; k < angles[s].size(); ++k) {
      int32_t line = line_of[s][k];
      if (line < 0) {
        line = static_cast<int32_t>(flow.lines.size());
        flow.lines.emplace_back();
        flow.stems.emplace_back();
        line_of[s][k] = line;
      }
      const float a = angles[s][k];
      for (int i = 0; i <= steps; ++i) {
        const float t = static_cast<float>(i) / static_cast<float>(steps);
        const float r = (1 - t) * c.base_radius_m + t * c.tip_radius_m;
        flow.lines[static_cast<size_t>(line)].push_back(axis_point(c, t) + r * (std::cos(a) * f.x + std::sin(a) * f.y));
        flow.stems[static_cast<size_t>(line)].push_back(static_cast<int32_t>(s));
      }
    }
    // Divide the ring among the children (the relinking of Table 2).
    float circumference_sum = 0;
    for (const int32_t ch : children[s]) circumference_sum += cones[static_cast<size_t>(ch)].base_radius_m;
    std::vector<float> centre(children[s].size()), half_arc(children[s].size());
    int32_t continuation = -1;
    for (size_t j = 0; j < children[s].size(); ++j) {
      const size_t ch = static_cast<size_t>(children[s][j]);
      if (!is_lateral(model, ch)) {
        continuation = static_cast<int32_t>(j);
        continue;
      }
      centre[j] = angle_in(f, frames[ch].z);
      half_arc[j] = kPi * cones[ch].base_radius_m / circumference_sum;
    }
    std::vector<std::vector<float>> child_angles(children[s].size());
    std::vector<std::vector<int32_t>> child_lines(children[s].size());
    for (size_t k = 0; k < angles[s].size(); ++k) {
      const float a = angles[s][k];
      int32_t to = continuation;
      float best = std::numeric_limits<float>::infinity();
      for (size_t j = 0; j < children[s].size(); ++j) {
        if (static_cast<int32_t>(j) == continuation) continue;
        const float diff = std::abs(std::remainder(a - centre[j], 2 * kPi));
        if (diff < half_arc[j] && diff < best) {
          best = diff;
          to = static_cast<int32_t>(j);
        }
      }
      if (to < 0) continue;  // no continuation: the particle has reached the tip
      const size_t ch = static_cast<size_t>(children[s][static_cast<size_t>(to)]);
      const Vec3 radial = std::cos(a) * f.x + std::sin(a) * f.y;
      float b;
      if (static_cast<int32_t>(to) == continuation) {
        b = angle_in(frames[ch], radial);
      } else {
        // The arc closes into a loop around the lateral, its two ends meeting on the lateral's
        // side facing back down the parent.
        const float u =
            std::remainder(a - centre[static_cast<size_t>(to)], 2 * kPi) / half_arc[static_cast<size_t>(to)];
        b = angle_in(frames[ch], -f.z) + kPi + kPi * u;
      }
      child_angles[static_cast<size_t>(to)].push_back(wrap(b));
      child_lines[static_cast<size_t>(to)].push_back(line_of[s][k]);
    }
    for (size_t j = 0; j < children[s].size(); ++j) {
      const size_t ch = static_cast<size_t>(children[s][j]);
      // Relinking may add or drop particles; a kept particle continues its line, a new one starts
      // its own.
      std::vector<float> ring = child_angles[j];
      respace(ring, 2 * kPi * cones[ch].base_radius_m, bark.spacing_m);
      std::vector<int32_t> lines(ring.size(), -1);
      for (size_t k = 0; k < ring.size(); ++k)
        for (size_t m = 0; m < child_angles[j].size(); ++m)
          if (child_angles[j][m] == ring[k] && child_lines[j][m] >= 0) {
            lines[k] = child_lines[j][m];
            child_lines[j][m] = -1;
            break;
          }
      angles[ch] = std::move(ring);
      line_of[ch] = std::move(lines);
    }
  }
  return flow;
}

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

}  // namespace

TriangleMesh hart_baker_bark(const TreeModel& model, const HartBakerParams& params, std::span<const JointPlan> joints) {
  const HartBakerBark& bark = params.bark;
  TriangleMesh mesh;
  if (bark.kind == BarkKind::Smooth) return mesh;
  const BarkFlow flow = hart_baker_bark_flow(model, params);
  std::vector<BlendCone> cones(model.stems.size());
  for (size_t s = 0; s < cones.size(); ++s) cones[s] = stem_cone(model, s).cone;
  auto add = [&](const Vec3& p, const Vec3& n) {
    mesh.positions.push_back(p);
    mesh.normals.push_back(n);
    mesh.uvs.emplace_back(0.0f, 0.0f);
    return static_cast<uint32_t>(mesh.positions.size() - 1);
  };
  const std::vector<std::vector<int32_t>> children = stem_children(model);
  auto inside_one = [&](int32_t other, const Vec3& x) {
    const ConeDistance cd = cone_distance(x, cones[static_cast<size_t>(other)]);
    return cd.d - cd.r < bark.size_m;
  };
  auto inside_neighbour = [&](size_t s, const Vec3& x) {
    const int32_t parent = model.stems.parent[s];
    if (parent >= 0) {
      if (inside_one(parent, x)) return true;
      for (const int32_t sibling : children[static_cast<size_t>(parent)])
        if (static_cast<size_t>(sibling) != s && inside_one(sibling, x)) return true;
    }
    for (const int32_t child : children[s])
      if (inside_one(child, x)) return true;
    return false;
  };
  const float lift = 0.05f * bark.height_m + 1e-4f;  // feature edges stand just off the tube
  for (size_t l = 0; l < flow.lines.size(); ++l) {
    const std::vector<Vec3>& line = flow.lines[l];
    for (size_t i = 0; i + 1 < line.size(); ++i) {
      const size_t s = static_cast<size_t>(flow.stems[l][i]);
      if (flow.stems[l][i + 1] != flow.stems[l][i]) continue;
      const BlendCone& c = cones[s];
      if (c.base_radius_m < bark.min_radius_m) continue;
      Pcg32 rng(hash_ids(0xba4cu, l, i));
      if (rng.uniform() >= bark.density) continue;
      const Vec3 along = glm::normalize(c.tip - c.base);
      const Vec3 p = line[i];
      const Vec3 to_axis = p - (c.base + along * glm::dot(p - c.base, along));
      if (glm::length(to_axis) <= 0) continue;
      const Vec3 n = glm::normalize(to_axis);
      const Vec3 across = glm::cross(along, n);
      // Jitter along the line so features do not line up in rows.
      Vec3 at = p + along * (bark.spacing_m * (rng.uniform() - 0.5f));
      // The whole feature on this limb.
      const float extent =
          0.5f * (bark.kind == BarkKind::Ribbon ? 1.3f * bark.length_m : 1.4f * bark.size_m * bark.aspect);
      const float limb_length = glm::length(c.tip - c.base);
      if (limb_length < 2 * extent) continue;
      at += along *
            (std::clamp(glm::dot(at - c.base, along), extent, limb_length - extent) - glm::dot(at - c.base, along));
      // Not where the limb runs inside its neighbours at a node (a lateral's base inside the
      // parent or its continuation, a parent's tip inside its children).
      if (inside_neighbour(s, at)) continue;
      // Where a stitched joint is the surface, onto it.
      float onto = 0;
      bool lost = false;
      for (const JointPlan& plan : joints)
        if (in_stitched(plan, at)) {
          float fillet = 0;
          for (const BlendJoint& j : plan.joints) fillet = std::max(fillet, j.fillet_m);
          const std::optional<float> d = to_joint_surface(plan, at, n, fillet + plan.cell_m);
          lost = !d;
          onto = d.value_or(0.0f);
          break;
        }
      if (lost) continue;
      const auto feature = static_cast<uint32_t>(mesh.positions.size());
      if (bark.kind == BarkKind::Spotted) {
        // A fan of triangles, its rim on the bark and its peak height_m above (§5.4).
        const float w = bark.size_m * (0.6f + 0.8f * rng.uniform()) * 0.5f;
        const float hgt = w * bark.aspect;
        const uint32_t peak = add(at + n * bark.height_m, n);
        constexpr int kRim = 8;
        const uint32_t first = static_cast<uint32_t>(mesh.positions.size());
        for (int k = 0; k < kRim; ++k) {
          const float a = 2 * kPi * static_cast<float>(k) / kRim;
          const Vec3 q = at + across * (w * std::cos(a)) + along * (hgt * std::sin(a));
          const Vec3 q_axis = c.base + along * glm::dot(q - c.base, along);
          const float t = std::clamp(glm::dot(q - c.base, along) / glm::length(c.tip - c.base), 0.0f, 1.0f);
          const float r = (1 - t) * c.base_radius_m + t * c.tip_radius_m;
          const Vec3 out = glm::normalize(q - q_axis);
          add(q_axis + out * (r + lift), out);
        }
        for (int k = 0; k < kRim; ++k)
          mesh.triangles.emplace_back(peak, first + static_cast<uint32_t>(k),
                                      first + static_cast<uint32_t>((k + 1) % kRim));
      } else {
        // A segmented ribbon along the grain, turned by a random twist, its ridge height_m above
        // the bark and its edges on it (§5.4).
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
            add((e == 0 ? q_axis + glm::normalize(q - q_axis) * r : o_axis + out * r) + out * rise,
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
      for (uint32_t v = feature; v < mesh.positions.size(); ++v) mesh.positions[v] += n * onto;
    }
  }
  // Face every triangle outward (along its vertices' normals).
  for (glm::uvec3& t : mesh.triangles) {
    const Vec3 nrm = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
    if (glm::dot(nrm, mesh.normals[t.x] + mesh.normals[t.y] + mesh.normals[t.z]) < 0) std::swap(t.y, t.z);
  }
  return mesh;
}

}  // namespace sylva
