// The Hart–Baker surface: blended cones (§5.2, eq. 26–30) polygonised at the joints by marching
// tetrahedra, tubes elsewhere, and bark (§5.4) from a particle flow over the limbs (§5.3).

#include "geometry/trees/hart_baker/surface.h"

#include "core/hash.h"
#include "core/rng.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace sylva {

namespace {

struct ConeDistance {
  float d;     // distance from x to the nearest axis point
  float r;     // the cone's radius there (eq. 27)
  Vec3 point;  // the nearest axis point
};

ConeDistance cone_distance(const Vec3& x, const BlendCone& c) {
  const Vec3 axis = c.tip - c.base;
  const float len2 = glm::dot(axis, axis);
  const float t = len2 > 0 ? std::clamp(glm::dot(x - c.base, axis) / len2, 0.0f, 1.0f) : 0.0f;
  const Vec3 p = c.base + axis * t;
  return {glm::length(x - p), (1 - t) * c.base_radius_m + t * c.tip_radius_m, p};
}

float segment_distance(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const float len2 = glm::dot(ab, ab);
  const float t = len2 > 0 ? std::clamp(glm::dot(x - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
  return glm::length(x - (a + ab * t));
}

}  // namespace

float blended_cones(const Vec3& x, std::span<const BlendCone> cones, const BlendJoint& joint) {
  // The paper blends the two nearest cones; where three or more limbs meet, which two are nearest
  // changes abruptly and so would the field. The pairwise blends' minimum is continuous and is the
  // paper's blend wherever one pair is the nearest by far.
  constexpr size_t kMost = 16;
  std::array<ConeDistance, kMost> near{};
  const size_t n = std::min(cones.size(), kMost);
  float f1 = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < n; ++i) {
    near[i] = cone_distance(x, cones[i]);
    f1 = std::min(f1, near[i].d - near[i].r);
  }
  const float s = std::max(0.0f, 1.0f - glm::length(x - joint.centre) / joint.reach_m);
  const float reach = joint.fillet_m * s * s;
  if (reach <= 0) return f1;
  float blend = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      // Eq. 26–30 (eq. 29's c taken as 1).
      const ConeDistance& a = near[i];
      const ConeDistance& b = near[j];
      const float d = segment_distance(x, a.point, b.point);
      const float sum = a.d + b.d;
      const float r = sum > 0 ? (b.d * a.r + a.d * b.r) / sum : a.r;
      blend = std::min(blend, d - r);
    }
  // Taken literally the blend fills everything between two axes (a point on the segment x1–x2 has
  // d = 0), so it is bounded: within the fillet of the cones' union, fading with the distance from
  // the joint, and never thinner than the union.
  return std::min(f1, std::max(blend, f1 - reach));
}

TriangleMesh polygonise_joint(std::span<const BlendCone> cones, const BlendJoint& joint, float half_m, int cells) {
  // Grid points 0..n, the outer layer (0 and n) forced outside so the surface closes.
  const int n = cells + 2;
  const float h = 2 * half_m / static_cast<float>(cells);
  const Vec3 origin = joint.centre - Vec3(half_m + h);
  const int side = n + 1;
  auto index = [&](int i, int j, int k) { return (static_cast<size_t>(k) * side + j) * side + i; };
  auto position = [&](int i, int j, int k) { return origin + h * Vec3(i, j, k); };
  std::vector<float> field(static_cast<size_t>(side) * side * side);
  std::vector<uint8_t> border(field.size());
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const bool outer = i == 0 || j == 0 || k == 0 || i == n || j == n || k == n;
        border[index(i, j, k)] = outer;
        field[index(i, j, k)] = outer ? h : blended_cones(position(i, j, k), cones, joint);
      }
  auto field_at = [&](const Vec3& x) { return blended_cones(x, cones, joint); };

  TriangleMesh mesh;
  std::unordered_map<uint64_t, uint32_t> edge_vertex;
  // The vertex where the surface crosses the grid edge a–b (a inside, b outside).
  auto vertex_on = [&](size_t a, size_t b, const Vec3& pa, const Vec3& pb) -> uint32_t {
    const uint64_t key = a < b ? (static_cast<uint64_t>(a) << 32 | b) : (static_cast<uint64_t>(b) << 32 | a);
    if (const auto it = edge_vertex.find(key); it != edge_vertex.end()) return it->second;
    float fa = field[a], fb = field[b];
    float ta = 0, tb = 1;
    float t = fa / (fa - fb);
    // Regula falsi (the Illinois variant) along the edge onto the surface, except on edges to
    // the forced-outside border, where the surface is the closing cap.
    if (!border[a] && !border[b]) {
      int side_kept = 0;
      for (int it = 0; it < 16 && fa != fb; ++it) {
        const float ft = field_at(pa + (pb - pa) * t);
        if (ft == 0) break;
        if (ft < 0) {
          ta = t;
          fa = ft;
          if (side_kept == -1) fb *= 0.5f;
          side_kept = -1;
        } else {
          tb = t;
          fb = ft;
          if (side_kept == 1) fa *= 0.5f;
          side_kept = 1;
        }
        t = ta + (tb - ta) * fa / (fa - fb);
      }
    }
    const Vec3 p = pa + (pb - pa) * t;
    const float e = 0.05f * h;
    Vec3 g(field_at(p + Vec3(e, 0, 0)) - field_at(p - Vec3(e, 0, 0)),
           field_at(p + Vec3(0, e, 0)) - field_at(p - Vec3(0, e, 0)),
           field_at(p + Vec3(0, 0, e)) - field_at(p - Vec3(0, 0, e)));
    const float gl = glm::length(g);
    const uint32_t v = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.push_back(p);
    mesh.normals.push_back(gl > 0 ? g / gl : Vec3(0, 0, 1));
    mesh.uvs.emplace_back(0.0f, 0.0f);
    edge_vertex.emplace(key, v);
    return v;
  };

  // A cube's corners and its six tetrahedra around the 0–6 diagonal.
  static constexpr std::array<std::array<int, 3>, 8> kCorner = {
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
  static constexpr std::array<std::array<int, 4>, 6> kTet = {
      {{0, 5, 1, 6}, {0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        std::array<size_t, 8> id;
        std::array<Vec3, 8> pos;
        int inside = 0;
        for (int c = 0; c < 8; ++c) {
          const auto& o = kCorner[static_cast<size_t>(c)];
          id[static_cast<size_t>(c)] = index(i + o[0], j + o[1], k + o[2]);
          pos[static_cast<size_t>(c)] = position(i + o[0], j + o[1], k + o[2]);
          inside += field[id[static_cast<size_t>(c)]] < 0;
        }
        if (inside == 0 || inside == 8) continue;
        for (const auto& tet : kTet) {
          std::array<int, 4> in{}, out{};
          int ni = 0, no = 0;
          for (int c : tet) {
            if (field[id[static_cast<size_t>(c)]] < 0)
              in[static_cast<size_t>(ni++)] = c;
            else
              out[static_cast<size_t>(no++)] = c;
          }
          if (ni == 0 || ni == 4) continue;
          auto v = [&](int a, int b) {
            return vertex_on(id[static_cast<size_t>(a)], id[static_cast<size_t>(b)], pos[static_cast<size_t>(a)],
                             pos[static_cast<size_t>(b)]);
          };
          // Orient each triangle so its normal points from the inside corners outward.
          auto emit = [&](uint32_t a, uint32_t b, uint32_t c, const Vec3& inside_point) {
            const Vec3 pa = mesh.positions[a], pb = mesh.positions[b], pc = mesh.positions[c];
            const Vec3 nrm = glm::cross(pb - pa, pc - pa);
            if (glm::dot(nrm, pa - inside_point) < 0) std::swap(b, c);
            mesh.triangles.emplace_back(a, b, c);
          };
          if (ni == 1) {
            emit(v(in[0], out[0]), v(in[0], out[1]), v(in[0], out[2]), pos[static_cast<size_t>(in[0])]);
          } else if (ni == 3) {
            emit(v(in[0], out[0]), v(in[1], out[0]), v(in[2], out[0]),
                 (pos[static_cast<size_t>(in[0])] + pos[static_cast<size_t>(in[1])] + pos[static_cast<size_t>(in[2])]) /
                     3.0f);
          } else {
            const uint32_t a = v(in[0], out[0]), b = v(in[0], out[1]), c = v(in[1], out[1]), d = v(in[1], out[0]);
            const Vec3 inside_point = (pos[static_cast<size_t>(in[0])] + pos[static_cast<size_t>(in[1])]) * 0.5f;
            emit(a, b, c, inside_point);
            emit(a, c, d, inside_point);
          }
        }
      }
  return mesh;
}

namespace {

struct StemCone {
  BlendCone cone;
  Vec3 lo, hi;  // bounds, radius included
};

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

bool is_lateral(const TreeModel& model, size_t s) {
  const int32_t p = model.stems.parent[s];
  return p >= 0 && model.stems.level[s] > model.stems.level[static_cast<size_t>(p)];
}

// The blended joints: one per node whose thickest lateral reaches the threshold.
void add_joints(const TreeModel& model, const HartBakerSurface& surface, TriangleMesh& out) {
  const size_t count = model.stems.size();
  std::vector<StemCone> cones(count);
  for (size_t s = 0; s < count; ++s) cones[s] = stem_cone(model, s);
  const std::vector<std::vector<int32_t>> children = stem_children(model);
  std::vector<BlendCone> nearby;
  for (size_t p = 0; p < count; ++p) {
    float lateral = 0;
    for (const int32_t c : children[p])
      if (is_lateral(model, static_cast<size_t>(c)))
        lateral = std::max(lateral, cones[static_cast<size_t>(c)].cone.base_radius_m);
    if (lateral <= 0 || lateral < surface.joint_min_radius_m) continue;
    const BlendCone& parent = cones[p].cone;
    const float parent_r = parent.tip_radius_m;
    BlendJoint joint{parent.tip, surface.reach * std::max(parent_r, lateral), surface.fillet * lateral};
    const float half = joint.reach_m * 1.1f;
    // The node's own limbs first (blended_cones reads at most 16), then any other limb in reach.
    nearby.clear();
    nearby.push_back(parent);
    for (const int32_t c : children[p]) nearby.push_back(cones[static_cast<size_t>(c)].cone);
    for (size_t s = 0; s < count; ++s) {
      if (s == p || model.stems.parent[s] == static_cast<int32_t>(p)) continue;
      const StemCone& c = cones[s];
      if (c.hi.x < joint.centre.x - half || c.lo.x > joint.centre.x + half || c.hi.y < joint.centre.y - half ||
          c.lo.y > joint.centre.y + half || c.hi.z < joint.centre.z - half || c.lo.z > joint.centre.z + half)
        continue;
      nearby.push_back(c.cone);
    }
    // Cells small enough that the thinnest limb at the node is several cells across.
    float thinnest = parent_r;
    for (const int32_t c : children[p]) thinnest = std::min(thinnest, cones[static_cast<size_t>(c)].cone.base_radius_m);
    const int cells = std::clamp(static_cast<int>(std::ceil(2 * half / (0.5f * thinnest))), 8, surface.joint_cells);
    append_mesh(out, polygonise_joint(nearby, joint, half, cells));
  }
}

Vec3 axis_point(const BlendCone& c, float t) { return c.base + (c.tip - c.base) * t; }

// The angle of direction v about a stem's frame (0 along frame.x).
float angle_in(const Frame& f, const Vec3& v) { return std::atan2(glm::dot(v, f.y), glm::dot(v, f.x)); }

float wrap(float a) {
  a = std::fmod(a, 2 * kPi);
  return a < 0 ? a + 2 * kPi : a;
}

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

TriangleMesh hart_baker_bark(const TreeModel& model, const HartBakerParams& params) {
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
    }
  }
  // Face every triangle outward (along its vertices' normals).
  for (glm::uvec3& t : mesh.triangles) {
    const Vec3 nrm = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
    if (glm::dot(nrm, mesh.normals[t.x] + mesh.normals[t.y] + mesh.normals[t.z]) < 0) std::swap(t.y, t.z);
  }
  return mesh;
}

TreeMesh make_hart_baker_mesh(const TreeModel& model, const HartBakerParams& params, const TreeMeshOptions& options) {
  TreeMesh mesh = make_tree_mesh(model, options);
  if (params.surface.blend) add_joints(model, params.surface, mesh.stems);
  append_mesh(mesh.stems, hart_baker_bark(model, params));
  return mesh;
}

}  // namespace sylva
