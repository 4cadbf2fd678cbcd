// The Hart–Baker surface: blended cones (§5.2, eq. 26–30) polygonised at the joints by marching
// tetrahedra, tubes elsewhere, and bark (§5.4) from a particle flow over the limbs (§5.3).

#include "geometry/trees/hart_baker/surface.h"

#include "core/hash.h"
#include "core/rng.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
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

// blended_cones with the union of the cones given as f1 (the same limbs, piece by piece).
float blend_field(const Vec3& x, std::span<const BlendCone> cones, float f1, const BlendJoint& joint) {
  // The paper blends the two nearest cones; where three or more limbs meet, which two are nearest
  // changes abruptly and so would the field. The pairwise blends' minimum is continuous and is the
  // paper's blend wherever one pair is the nearest by far.
  const float s = std::max(0.0f, 1.0f - glm::length(x - joint.centre) / joint.reach_m);
  const float reach = joint.fillet_m * s * s;
  if (reach <= 0) return f1;
  constexpr size_t kMost = 16;
  std::array<ConeDistance, kMost> near{};
  const size_t n = std::min(cones.size(), kMost);
  for (size_t i = 0; i < n; ++i) near[i] = cone_distance(x, cones[i]);
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
  // the joint, and never thinner than the union. The bounds are rounded (a quadratic smooth
  // minimum and maximum over 0.4 of the fillet there) so the fillet meets the limbs without a
  // crease; the floor at 0.8 of the fillet and the rounding's 0.1 keep it within the fillet.
  const float k = 0.4f * reach;
  auto smin = [&](float a, float b) {
    const float h = std::max(k - std::abs(a - b), 0.0f) / k;
    return std::min(a, b) - h * h * k * 0.25f;
  };
  return smin(f1, -smin(-blend, 0.8f * reach - f1));
}

}  // namespace

float blended_cones(const Vec3& x, std::span<const BlendCone> cones, const BlendJoint& joint) {
  float f1 = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < std::min<size_t>(cones.size(), 16); ++i) {
    const ConeDistance cd = cone_distance(x, cones[i]);
    f1 = std::min(f1, cd.d - cd.r);
  }
  return blend_field(x, cones, f1, joint);
}

namespace {

// Marching tetrahedra over the box of `cells` cells of side h from `lo` (polygonise_joint), the
// surface of `field_at`, its normals the gradient of `normal_at`.
//
// Only the signs of the grid values decide the triangles, and only values next to a sign change or
// the border are read again, so far from the surface a block of grid points takes the value at
// its centre: the field lies between f1 − fillet·s² and f1 (blended_cones), f1 a union of cones
// changing by at most 1.2 per metre, so a centre value beyond 1.2 × (the block's reach plus a
// cell's diagonal) + the most fillet·s² of the joints in `joints` over that ball gives the whole
// block and its neighbours the same sign.
template <class Field, class Normal>
TriangleMesh polygonise_box(const Field& field_at, const Normal& normal_at, const Vec3& lo, const glm::ivec3& cells,
                            float h, std::span<const BlendJoint> joints) {
  // Grid points 0..n, the outer layer (0 and n) forced outside so the surface closes.
  const glm::ivec3 n = cells + 2;
  const Vec3 origin = lo - Vec3(h);
  auto index = [&](int i, int j, int k) {
    return (static_cast<size_t>(k) * static_cast<size_t>(n.y + 1) + static_cast<size_t>(j)) *
               static_cast<size_t>(n.x + 1) +
           static_cast<size_t>(i);
  };
  auto position = [&](int i, int j, int k) { return origin + h * Vec3(i, j, k); };
  std::vector<float> field(static_cast<size_t>(n.x + 1) * static_cast<size_t>(n.y + 1) * static_cast<size_t>(n.z + 1));
  std::vector<uint8_t> border(field.size());
  constexpr int kBlock = 4;
  const float ball = (0.5f * kBlock + 1) * std::sqrt(3.0f) * h;
  for (int bk = 0; bk <= n.z; bk += kBlock)
    for (int bj = 0; bj <= n.y; bj += kBlock)
      for (int bi = 0; bi <= n.x; bi += kBlock) {
        const Vec3 c = origin + h * (Vec3(bi, bj, bk) + 0.5f * static_cast<float>(kBlock - 1));
        float fillet = 0;
        for (const BlendJoint& j : joints) {
          const float s = std::max(0.0f, 1.0f - (glm::length(c - j.centre) - ball) / j.reach_m);
          fillet = std::max(fillet, j.fillet_m * std::min(1.0f, s) * std::min(1.0f, s));
        }
        const float centre = field_at(c);
        const bool uniform = std::abs(centre) > 1.2f * ball + fillet;
        for (int k = bk; k <= std::min(bk + kBlock - 1, n.z); ++k)
          for (int j = bj; j <= std::min(bj + kBlock - 1, n.y); ++j)
            for (int i = bi; i <= std::min(bi + kBlock - 1, n.x); ++i) {
              const bool outer = i == 0 || j == 0 || k == 0 || i == n.x || j == n.y || k == n.z;
              const bool edge = i == 1 || j == 1 || k == 1 || i == n.x - 1 || j == n.y - 1 || k == n.z - 1;
              border[index(i, j, k)] = outer;
              field[index(i, j, k)] = outer ? h : uniform && !edge ? centre : field_at(position(i, j, k));
            }
      }

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
        if (std::abs(ft) <= 1e-3f * h) break;  // micrometres: on the surface
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
    // Not at a grid point: the vertices of the edges meeting there stay apart.
    t = std::clamp(t, 1e-3f, 1 - 1e-3f);
    const Vec3 p = pa + (pb - pa) * t;
    const float e = 0.05f * h;
    Vec3 g(normal_at(p + Vec3(e, 0, 0)) - normal_at(p - Vec3(e, 0, 0)),
           normal_at(p + Vec3(0, e, 0)) - normal_at(p - Vec3(0, e, 0)),
           normal_at(p + Vec3(0, 0, e)) - normal_at(p - Vec3(0, 0, e)));
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
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
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

}  // namespace

TriangleMesh polygonise_joint(std::span<const BlendCone> cones, const BlendJoint& joint, float half_m, int cells) {
  const float h = 2 * half_m / static_cast<float>(cells);
  auto field = [&](const Vec3& x) { return blended_cones(x, cones, joint); };
  return polygonise_box(field, field, joint.centre - Vec3(half_m), glm::ivec3(cells), h, std::span(&joint, 1));
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

// A node with a blended joint.
struct NodeJoint {
  int32_t stem;  // the joint sits at its tip
  BlendJoint joint;
  float half;     // the closed joint's cube: half-size,
  int cells;      // cells across
  float cell;     // and their size
  float lateral;  // the thickest lateral's base radius
  float far;      // how far out its limbs are cut at least
};

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

// The signed distance to a tube piece: across its axis to the round cone or, with `polygon`, to its
// polygon (corners rounded by rounding_m); along it to its ring planes (so that consecutive pieces meet
// exactly, as the tube's bands do at their shared ring).
float piece_distance(const Vec3& x, const TubePiece& p, bool polygon) {
  const Vec3 axis = p.cone.tip - p.cone.base;
  const float len2 = glm::dot(axis, axis);
  if (len2 <= 0) return std::numeric_limits<float>::infinity();
  const float t = glm::dot(x - p.cone.base, axis) / len2;
  const Vec3 q = x - (p.cone.base + axis * t);
  const float tc = std::clamp(t, 0.0f, 1.0f);
  const float r = (1 - tc) * p.cone.base_radius_m + tc * p.cone.tip_radius_m;
  float across = glm::length(q) - r;
  if (polygon && p.sides >= 3) {
    // The polygon moved in by ρ, rounded out by ρ: the distance to the inset flat facing x, or
    // beyond the end of that flat to its corner, less ρ.
    const float sector = 2 * kPi / static_cast<float>(p.sides);
    const float a = wrap(std::atan2(glm::dot(q, p.ey), glm::dot(q, p.ex)));
    const float mid = (std::floor(a / sector) + 0.5f) * sector;
    const float side = a < mid ? -1.0f : 1.0f;
    const Vec3 normal = std::cos(mid) * p.ex + std::sin(mid) * p.ey;
    const Vec3 along = side * (std::cos(mid) * p.ey - std::sin(mid) * p.ex);
    const float apothem = r * std::cos(0.5f * sector);
    const float rho = std::min(p.rounding_m, 0.5f * apothem);
    const float inset = apothem - rho, half_side = inset * std::tan(0.5f * sector);
    const float d = glm::dot(q, normal) - inset, beside = glm::dot(q, along);
    across = (beside > half_side && d > 0 ? glm::length(q - normal * inset - along * half_side) : d) - rho;
  }
  const float ends = std::max(glm::dot(p.cone.base - x, p.base_axis), glm::dot(x - p.cone.tip, p.tip_axis));
  return std::max(across, ends);
}

// A ball holding a tube piece (its centre, and the most a point of the piece lies from it).
struct PieceBall {
  Vec3 centre;
  float radius;
};

std::vector<PieceBall> piece_balls(std::span<const TubePiece> pieces) {
  std::vector<PieceBall> balls;
  for (const TubePiece& p : pieces)
    balls.push_back({0.5f * (p.cone.base + p.cone.tip), 0.5f * glm::length(p.cone.tip - p.cone.base) +
                                                            std::max(p.cone.base_radius_m, p.cone.tip_radius_m)});
  return balls;
}

// Whether a piece, at least |x − centre| − radius from x, is certainly further than `bound`.
bool beyond(const Vec3& x, std::span<const PieceBall> balls, size_t i, float bound) {
  if (balls.empty()) return false;
  const float reach = bound + balls[i].radius;
  const Vec3 d = x - balls[i].centre;
  return reach < 0 || glm::dot(d, d) > reach * reach;
}

// The union of tube pieces: round, or as polygons. A polygon lies inside its circle by at most
// r (1 − cos(π/sides)) ≤ r (π/sides)²/2, so only pieces that close to the nearest round one are
// measured as polygons. `balls` (empty, or one per piece) skip the pieces certainly too far.
float pieces_union(const Vec3& x, std::span<const TubePiece> pieces, std::span<const PieceBall> balls, bool round) {
  if (round) {
    // For normals: the round cones with their round ends, whose gradient is radial across a ring
    // (a ring plane's own gradient, along the axis, would win within the polygon's sag of it).
    float least = std::numeric_limits<float>::infinity();
    for (size_t i = 0; i < pieces.size(); ++i) {
      if (beyond(x, balls, i, least)) continue;
      const ConeDistance cd = cone_distance(x, pieces[i].cone);
      least = std::min(least, cd.d - cd.r);
    }
    return least;
  }
  constexpr size_t kKept = 64;
  std::array<float, kKept> kept{};
  float bound = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < pieces.size(); ++i) {
    const TubePiece& p = pieces[i];
    const float f = beyond(x, balls, i, bound) ? std::numeric_limits<float>::infinity() : piece_distance(x, p, false);
    if (i < kKept) kept[i] = f;
    const float a = p.sides >= 3 ? kPi / static_cast<float>(p.sides) : 0.0f;
    bound = std::min(bound, f + std::max(p.cone.base_radius_m, p.cone.tip_radius_m) * 0.5f * a * a);
  }
  float f = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < pieces.size(); ++i) {
    const float r = i < kKept ? kept[i] : beyond(x, balls, i, bound) ? bound + 1 : piece_distance(x, pieces[i], false);
    if (r <= bound) f = std::min(f, piece_distance(x, pieces[i], true));
  }
  return f;
}

// The field of a joint plan: its joints' blends of its cones, the least (JointPlan).
float plan_field(const Vec3& x, std::span<const BlendCone> cones, std::span<const TubePiece> pieces,
                 std::span<const PieceBall> balls, std::span<const BlendJoint> joints, bool round) {
  float f = std::numeric_limits<float>::infinity();
  if (pieces.empty()) {
    for (const BlendJoint& j : joints) f = std::min(f, blended_cones(x, cones, j));
    return f;
  }
  const float f1 = pieces_union(x, pieces, balls, round);
  for (const BlendJoint& j : joints) f = std::min(f, blend_field(x, cones, f1, j));
  return f;
}

// A field's gradient by central differences (not divided by the step).
template <class Field>
Vec3 field_gradient(const Field& f, const Vec3& p, float e) {
  return Vec3(f(p + Vec3(e, 0, 0)) - f(p - Vec3(e, 0, 0)), f(p + Vec3(0, e, 0)) - f(p - Vec3(0, e, 0)),
              f(p + Vec3(0, 0, e)) - f(p - Vec3(0, 0, e)));
}

// The angle of p about the axis through `centre` along unit `axis`, in [0, 2π), from `e0`.
float angle_about(const Vec3& p, const Vec3& centre, const Vec3& axis, const Vec3& e0) {
  const Vec3 d = p - centre;
  return wrap(std::atan2(glm::dot(d, glm::cross(axis, e0)), glm::dot(d, e0)));
}

// Opens the closed joint mesh where a limb leaves it: drops what lies beyond the cut's plane
// within its cylinder and splits the triangles crossing the plane. The new vertices — one loop —
// are moved onto the field's zero set within the plane, given the field's gradient as normal, and
// returned in order around the limb. False (mesh untouched) when the cut is not clean: something
// else crosses the cylinder beyond the plane, or the boundary is not one loop around the axis.
template <class Field, class Normal>
bool open_joint(TriangleMesh& mesh, JointCut& cut, const Field& field, const Normal& normal_at, float cell) {
  const Vec3 u = cut.normal;
  const size_t nv = mesh.positions.size();
  std::vector<float> d(nv);
  std::vector<uint8_t> state(nv);  // 0 kept, 1 removed (beyond, in the cylinder), 2 beyond but outside
  // A vertex (nearly) on the plane would leave crossings (nearly) on top of it: the plane moves out
  // a little until none is within a thousandth of a cell.
  for (int attempt = 0;; ++attempt) {
    float nearest = std::numeric_limits<float>::infinity();
    for (size_t v = 0; v < nv; ++v) {
      const Vec3 rel = mesh.positions[v] - cut.origin;
      d[v] = glm::dot(rel, u);
      nearest = std::min(nearest, std::abs(d[v]) < cut.radius_m + cell ? std::abs(d[v]) : nearest);
      state[v] = d[v] <= 0 ? 0 : glm::length(rel - u * d[v]) < cut.radius_m ? 1 : 2;
    }
    if (nearest >= 1e-3f * cell) break;
    if (attempt == 8) return false;
    cut.origin += u * (2e-3f * cell);
    cut.gap_m -= 2e-3f * cell;
  }
  TriangleMesh out;
  out.positions = mesh.positions;
  out.normals = mesh.normals;
  out.uvs = mesh.uvs;
  std::unordered_map<uint64_t, uint32_t> crossing;
  std::unordered_map<uint32_t, uint32_t> next;  // the loop's directed edges
  auto cross = [&](uint32_t a, uint32_t b) {
    const uint64_t key = static_cast<uint64_t>(a) << 32 | b;  // a kept, b removed
    if (const auto it = crossing.find(key); it != crossing.end()) return it->second;
    const float t = d[a] / (d[a] - d[b]);
    const uint32_t v = static_cast<uint32_t>(out.positions.size());
    out.positions.push_back(out.positions[a] + (out.positions[b] - out.positions[a]) * t);
    out.normals.push_back(out.normals[a]);
    out.uvs.emplace_back(0.0f, 0.0f);
    crossing.emplace(key, v);
    return v;
  };
  for (const glm::uvec3& t : mesh.triangles) {
    const int removed = (state[t.x] == 1) + (state[t.y] == 1) + (state[t.z] == 1);
    if (removed == 0) {
      out.triangles.push_back(t);
      continue;
    }
    if (removed == 3) continue;
    if (state[t.x] == 2 || state[t.y] == 2 || state[t.z] == 2) return false;
    std::array<uint32_t, 4> poly{};
    size_t n = 0;
    uint32_t leave = 0, enter = 0;
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = t[e], b = t[(e + 1) % 3];
      if (state[a] == 0) poly[n++] = a;
      if (state[a] == 0 && state[b] == 1) leave = poly[n++] = cross(a, b);
      if (state[a] == 1 && state[b] == 0) enter = poly[n++] = cross(b, a);
    }
    // The kept polygon runs … → leave → enter → …: that edge lies on the plane, on the loop.
    if (!next.emplace(leave, enter).second) return false;
    out.triangles.emplace_back(poly[0], poly[1], poly[2]);
    if (n == 4) out.triangles.emplace_back(poly[0], poly[2], poly[3]);
  }
  // One loop through every new vertex.
  if (next.size() != crossing.size() || next.size() < 3) return false;
  std::vector<uint32_t> loop;
  for (uint32_t v = next.begin()->first;;) {
    loop.push_back(v);
    const auto it = next.find(v);
    if (it == next.end()) return false;
    v = it->second;
    if (v == loop.front()) break;
    if (loop.size() > next.size()) return false;
  }
  if (loop.size() != next.size()) return false;
  // Onto the zero set, along the plane's radius through the vertex (Illinois regula falsi within a
  // cell either side).
  const float e = 0.05f * cell;
  for (const uint32_t v : loop) {
    const Vec3 p = out.positions[v];
    const Vec3 q = (p - cut.origin) - u * glm::dot(p - cut.origin, u);
    const float r0 = glm::length(q);
    if (r0 <= 0) return false;
    const Vec3 axis = p - q, dir = q / r0;
    float lo = std::max(0.0f, r0 - cell), hi = r0 + cell;
    float flo = field(axis + dir * lo), fhi = field(axis + dir * hi);
    if (flo >= 0 || fhi <= 0) return false;
    float r = r0;
    int kept = 0;
    for (int it = 0; it < 40; ++it) {
      r = lo + (hi - lo) * flo / (flo - fhi);
      const float fr = field(axis + dir * r);
      if (std::abs(fr) <= 1e-7f || hi - lo <= 1e-7f) break;
      if (fr < 0) {
        lo = r, flo = fr;
        if (kept == -1) fhi *= 0.5f;
        kept = -1;
      } else {
        hi = r, fhi = fr;
        if (kept == 1) flo *= 0.5f;
        kept = 1;
      }
    }
    const Vec3 x = axis + dir * r;
    if (glm::length(x - p) > cell || r >= cut.radius_m) return false;
    out.positions[v] = x;
    const Vec3 g = field_gradient(normal_at, x, e);
    out.normals[v] = glm::length(g) > 0 ? glm::normalize(g) : out.normals[v];
  }
  // Crossings of a sliver may land on (nearly) the same point: each such loop edge collapses, its
  // triangle with it.
  std::vector<uint32_t> kept;
  std::unordered_map<uint32_t, uint32_t> alias;
  for (const uint32_t v : loop) {
    if (!kept.empty() && glm::length(out.positions[v] - out.positions[kept.back()]) < 1e-3f * cell)
      alias.emplace(v, kept.back());
    else
      kept.push_back(v);
  }
  while (kept.size() > 1 && glm::length(out.positions[kept.back()] - out.positions[kept.front()]) < 1e-3f * cell) {
    alias.emplace(kept.back(), kept.front());
    for (auto& [from, to] : alias)
      if (to == kept.back()) to = kept.front();
    kept.pop_back();
  }
  if (kept.size() < 3) return false;
  if (!alias.empty()) {
    std::vector<glm::uvec3> triangles;
    triangles.reserve(out.triangles.size());
    for (glm::uvec3 t : out.triangles) {
      for (int e = 0; e < 3; ++e)
        if (const auto it = alias.find(t[e]); it != alias.end()) t[e] = it->second;
      if (t.x != t.y && t.y != t.z && t.z != t.x) triangles.push_back(t);
    }
    out.triangles = std::move(triangles);
  }
  loop = std::move(kept);
  // Once around the axis, in one direction (a vertex may fall back a little where marching
  // tetrahedra left two crossings close together; the band's walk tolerates that).
  const Vec3 e0 = Frame::from_z(u).x;
  std::vector<float> steps(loop.size());
  float turned = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const float a = angle_about(out.positions[loop[i]], cut.origin, u, e0);
    const float b = angle_about(out.positions[loop[(i + 1) % loop.size()]], cut.origin, u, e0);
    steps[i] = std::remainder(b - a, 2 * kPi);
    turned += steps[i];
  }
  if (std::abs(std::abs(turned) - 2 * kPi) > 0.1f) return false;
  const float back = 0.5f * 2 * kPi / static_cast<float>(loop.size());
  for (const float step : steps)
    if (step * turned < 0 && std::abs(step) > back) return false;
  cut.loop = std::move(loop);
  mesh = std::move(out);
  return true;
}

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

// How a cluster of joints is laid out as one surface with the tubes.
struct ClusterLayout {
  enum class Result { Ok, Join, Fails } result = Result::Fails;
  int32_t join = -1;  // the joint to take into the cluster (Join)
  std::vector<int32_t> field;
  std::vector<JointCut> cuts;
  std::vector<int32_t> inside;
  Vec3 lo{0.0f}, hi{0.0f};
  float cell = 0;
};

// Lays out a cluster of joints (docs/hart_baker.md "Blended joints"): every limb at its nodes (the
// parent down, each child at least half a cell thick up) is followed out of the blends, through
// the stretches joining two of its nodes, and cut where every blend has faded and no other limb
// is within two cells, with a ring 1.5 cells further out; the box holds the nodes' cubes, the
// limbs inside and the cuts.
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
  TriangleMesh mesh = polygonise_box(field, round, layout.lo, cells, layout.cell, plan.joints);
  std::vector<JointCut> cuts = layout.cuts;
  for (JointCut& c : cuts)
    if (!open_joint(mesh, c, field, round, layout.cell)) return false;
  plan.lo = layout.lo;
  plan.hi = layout.lo + Vec3(cells) * layout.cell;
  plan.cell_m = layout.cell;
  plan.cuts = std::move(cuts);
  plan.inside = layout.inside;
  plan.mesh = std::move(mesh);
  plan.stitched = true;
  return true;
}

// Where the shared mesher put a stem's tube in its stems mesh (make_tree_mesh's layout: a base
// cap centre, `rings` rings of m + 1 vertices, a tip vertex; m base-cap triangles, 2m per band,
// m at the tip).
struct TubeLayout {
  uint32_t first_vertex = 0, first_triangle = 0, triangles = 0, m = 0, rings = 0;
};

std::vector<TubeLayout> tube_layout(const TreeModel& model, const TreeMeshOptions& options) {
  std::vector<TubeLayout> layout(model.stems.size());
  uint32_t vertices = 0, triangles = 0;
  for (size_t s = 0; s < model.stems.size(); ++s) {
    const uint32_t count = model.stems.section_count[s];
    if (count < 2 || (options.split_dead_stems && model.stems.is_dead(s))) continue;
    TubeLayout& l = layout[s];
    l.m = static_cast<uint32_t>(radial_segments_for_level(options, model.stems.level[s], model.stems.lobes[s]));
    const uint32_t last = model.stems.first_section[s] + count - 1;
    l.rings = model.sections.radius_m[last] <= 1e-7f ? count - 1 : count;
    l.first_vertex = vertices;
    l.first_triangle = triangles;
    l.triangles = l.m + (l.rings - 1) * 2 * l.m + l.m;
    vertices += 2 + l.rings * (l.m + 1);
    triangles += l.triangles;
  }
  return layout;
}

// The band between a cut's open loop (joint vertices) and its ring (tube vertices ring..ring+m,
// the last repeating the first): both walked once around the limb's axis by angle, merged.
void zipper(TriangleMesh& mesh, const JointCut& cut, uint32_t loop_offset, uint32_t ring, uint32_t m) {
  const Vec3 u = cut.normal;
  const Vec3 centre = cut.origin + u * cut.gap_m;
  Vec3 e0 = mesh.positions[ring] - centre;
  e0 = glm::normalize(e0 - u * glm::dot(e0, u));
  std::vector<uint32_t> a(m + 1);
  for (uint32_t j = 0; j <= m; ++j) a[j] = ring + j;
  // The ring as the tube made it may turn either way about u.
  if (angle_about(mesh.positions[ring + 1], centre, u, e0) > kPi) std::reverse(a.begin(), a.end());
  std::vector<float> aa(m + 1);
  for (uint32_t j = 0; j < m; ++j) aa[j] = angle_about(mesh.positions[a[j]], centre, u, e0);
  aa[0] = 0;
  aa[m] = 2 * kPi;
  // The loop from its least angle, turning the same way.
  std::vector<uint32_t> b(cut.loop.size());
  for (size_t k = 0; k < b.size(); ++k) b[k] = cut.loop[k] + loop_offset;
  auto angle = [&](uint32_t v) { return angle_about(mesh.positions[v], cut.origin, u, e0); };
  float turned = 0;
  for (size_t k = 0; k < b.size(); ++k) turned += std::remainder(angle(b[(k + 1) % b.size()]) - angle(b[k]), 2 * kPi);
  if (turned < 0) std::reverse(b.begin(), b.end());
  size_t least = 0;
  for (size_t k = 1; k < b.size(); ++k)
    if (angle(b[k]) < angle(b[least])) least = k;
  std::rotate(b.begin(), b.begin() + static_cast<ptrdiff_t>(least), b.end());
  // Unwrapped: from the least angle once around, small steps back allowed.
  std::vector<float> ba(b.size() + 1);
  ba[0] = angle(b[0]);
  for (size_t k = 1; k < b.size(); ++k) ba[k] = ba[k - 1] + std::remainder(angle(b[k]) - angle(b[k - 1]), 2 * kPi);
  b.push_back(b.front());
  ba.back() = ba[0] + 2 * kPi;
  auto emit = [&](uint32_t p, uint32_t q, uint32_t r) {
    const Vec3 pp = mesh.positions[p], pq = mesh.positions[q], pr = mesh.positions[r];
    const Vec3 mid = (pp + pq + pr) / 3.0f;
    const Vec3 out = mid - (cut.origin + u * glm::dot(mid - cut.origin, u));
    if (glm::dot(glm::cross(pq - pp, pr - pp), out) < 0) std::swap(q, r);
    mesh.triangles.emplace_back(p, q, r);
  };
  size_t i = 0, k = 0;
  const size_t n = b.size() - 1;
  while (i < m || k < n) {
    const bool ring_next = k == n || (i < m && aa[i + 1] <= ba[k + 1]);
    if (ring_next) {
      emit(a[i], a[i + 1], b[k]);
      ++i;
    } else {
      emit(a[i], b[k + 1], b[k]);
      ++k;
    }
  }
}

// Puts the joints into the tubes' mesh: stitched joints replace the tubes between their node and
// their rings and are zipped to the rings; the others are added closed.
void add_joints(TriangleMesh& stems, const TreeModel& ringed, const std::vector<JointPlan>& plans,
                const TreeMeshOptions& options) {
  const std::vector<TubeLayout> layout = tube_layout(ringed, options);
  std::vector<uint8_t> dropped(stems.triangles.size(), 0);
  auto drop = [&](uint32_t from, uint32_t to) { std::fill(dropped.begin() + from, dropped.begin() + to, 1); };
  for (const JointPlan& plan : plans) {
    const uint32_t offset = static_cast<uint32_t>(stems.positions.size());
    append_mesh(stems, plan.mesh);
    if (!plan.stitched) continue;
    for (const int32_t s : plan.inside) {
      const TubeLayout& l = layout[static_cast<size_t>(s)];
      drop(l.first_triangle, l.first_triangle + l.triangles);
    }
    for (const JointCut& cut : plan.cuts) {
      const size_t s = static_cast<size_t>(cut.stem);
      const TubeLayout& l = layout[s];
      const uint32_t first = ringed.stems.first_section[s];
      // with_rings put a section at exactly this arc (or the walk snapped to one).
      uint32_t k = 0;
      while (k + 1 < ringed.stems.section_count[s] && ringed.sections.arc_m[first + k] != cut.ring_arc_m) ++k;
      const uint32_t band = l.first_triangle + l.m + 2 * l.m * k;
      if (cut.toward_tip)
        drop(l.first_triangle, band);
      else
        drop(band, l.first_triangle + l.triangles);
      zipper(stems, cut, offset, l.first_vertex + 1 + k * (l.m + 1), l.m);
    }
  }
  // Drop the trimmed triangles and the vertices nothing uses any more.
  std::vector<glm::uvec3> kept;
  kept.reserve(stems.triangles.size());
  for (size_t t = 0; t < stems.triangles.size(); ++t)
    if (t >= dropped.size() || !dropped[t]) kept.push_back(stems.triangles[t]);
  std::vector<uint32_t> index(stems.positions.size(), std::numeric_limits<uint32_t>::max());
  for (const glm::uvec3& t : kept)
    for (int e = 0; e < 3; ++e) index[t[e]] = 0;
  uint32_t used = 0;
  for (size_t v = 0; v < index.size(); ++v)
    if (index[v] == 0) {
      index[v] = used;
      stems.positions[used] = stems.positions[v];
      if (!stems.normals.empty()) stems.normals[used] = stems.normals[v];
      if (!stems.uvs.empty()) stems.uvs[used] = stems.uvs[v];
      ++used;
    }
  stems.positions.resize(used);
  if (!stems.normals.empty()) stems.normals.resize(used);
  if (!stems.uvs.empty()) stems.uvs.resize(used);
  for (glm::uvec3& t : kept) t = glm::uvec3(index[t.x], index[t.y], index[t.z]);
  stems.triangles = std::move(kept);
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

}  // namespace

HartBakerJoints plan_hart_baker_joints(const TreeModel& model, const HartBakerSurface& surface,
                                       const TreeMeshOptions& options) {
  const size_t count = model.stems.size();
  std::vector<StemCone> cones(count);
  for (size_t s = 0; s < count; ++s) cones[s] = stem_cone(model, s);
  const std::vector<std::vector<int32_t>> children = stem_children(model);
  std::vector<int32_t> joint_of(count, -1);
  std::vector<NodeJoint> nodes;
  float ahead = 0;
  for (size_t p = 0; p < count; ++p) {
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
  // Clusters: joints whose limbs meet before both are cut, or whose trims would overlap, are laid
  // out together (union–find, the least index the root).
  std::vector<size_t> root(nodes.size());
  for (size_t j = 0; j < nodes.size(); ++j) root[j] = j;
  auto find = [&](size_t j) {
    while (root[j] != j) j = root[j] = root[root[j]];
    return j;
  };
  auto unite = [&](size_t a, size_t b) {
    a = find(a), b = find(b);
    if (a != b) root[std::max(a, b)] = std::min(a, b);
  };
  constexpr size_t kMostJoints = 8;
  std::vector<std::vector<size_t>> members;
  std::vector<ClusterLayout> layouts;
  for (bool changed = true; changed;) {
    changed = false;
    members.assign(nodes.size(), {});
    for (size_t j = 0; j < nodes.size(); ++j) members[find(j)].push_back(j);
    layouts.assign(nodes.size(), ClusterLayout{});
    for (size_t c = 0; c < nodes.size(); ++c) {
      if (members[c].empty() || members[c].size() > kMostJoints) continue;
      layouts[c] = layout_cluster(members[c], model, children, joint_of, nodes, cones, ahead);
      if (layouts[c].result == ClusterLayout::Result::Join) {
        unite(c, static_cast<size_t>(layouts[c].join));
        changed = true;
      }
    }
    if (changed) continue;
    // Two clusters may not trim the same stretch of a tube.
    struct Trim {
      size_t cluster;
      float lo, hi;
    };
    std::vector<std::vector<Trim>> trims(count);
    constexpr float kAll = std::numeric_limits<float>::infinity();
    for (size_t c = 0; c < nodes.size(); ++c) {
      if (layouts[c].result != ClusterLayout::Result::Ok) continue;
      for (const int32_t s : layouts[c].inside) trims[static_cast<size_t>(s)].push_back({c, -kAll, kAll});
      for (const JointCut& cut : layouts[c].cuts)
        trims[static_cast<size_t>(cut.stem)].push_back(
            {c, cut.toward_tip ? -kAll : cut.ring_arc_m, cut.toward_tip ? cut.ring_arc_m : kAll});
    }
    for (const std::vector<Trim>& on : trims)
      for (size_t a = 0; a < on.size(); ++a)
        for (size_t b = a + 1; b < on.size(); ++b)
          if (on[a].cluster != on[b].cluster && on[a].lo <= on[b].hi && on[b].lo <= on[a].hi) {
            unite(on[a].cluster, on[b].cluster);
            changed = true;
          }
  }
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

float joint_plan_field(const JointPlan& plan, const Vec3& x, bool round) {
  return plan_field(x, plan.cones, plan.pieces, {}, plan.joints, round);
}

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

TreeMesh make_hart_baker_mesh(const TreeModel& model, const HartBakerParams& params, const TreeMeshOptions& options) {
  if (!params.surface.blend) {
    TreeMesh mesh = make_tree_mesh(model, options);
    append_mesh(mesh.stems, hart_baker_bark(model, params));
    return mesh;
  }
  const HartBakerJoints joints = plan_hart_baker_joints(model, params.surface, options);
  TreeMesh mesh = make_tree_mesh(joints.ringed, options);
  add_joints(mesh.stems, joints.ringed, joints.plans, options);
  append_mesh(mesh.stems, hart_baker_bark(model, params, joints.plans));
  return mesh;
}

}  // namespace sylva
