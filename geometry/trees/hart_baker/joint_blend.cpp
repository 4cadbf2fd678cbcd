// The Hart–Baker joints' blend field: blended cones (§5.2, eq. 26–30), and the surface of a field
// polygonised by marching tetrahedra.

#include "geometry/trees/hart_baker/surface_detail.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace sylva {

namespace surface_detail {

ConeDistance cone_distance(const Vec3& x, const BlendCone& c) {
  const Vec3 axis = c.tip - c.base;
  const float len2 = glm::dot(axis, axis);
  const float t = len2 > 0 ? std::clamp(glm::dot(x - c.base, axis) / len2, 0.0f, 1.0f) : 0.0f;
  const Vec3 p = c.base + axis * t;
  return {glm::length(x - p), (1 - t) * c.base_radius_m + t * c.tip_radius_m, p};
}

namespace {

float segment_distance(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const float len2 = glm::dot(ab, ab);
  const float t = len2 > 0 ? std::clamp(glm::dot(x - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
  return glm::length(x - (a + ab * t));
}

}  // namespace

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

namespace {

// polygonise_box's grid: points 0..n along each axis from `origin`, h apart, the outer layer
// (0 and n) forced outside so the surface closes.
struct Grid {
  glm::ivec3 n;
  Vec3 origin;
  float h;
  std::vector<float> field;
  std::vector<uint8_t> border;

  size_t index(int i, int j, int k) const {
    return (static_cast<size_t>(k) * static_cast<size_t>(n.y + 1) + static_cast<size_t>(j)) *
               static_cast<size_t>(n.x + 1) +
           static_cast<size_t>(i);
  }
  Vec3 position(int i, int j, int k) const { return origin + h * Vec3(i, j, k); }
};

// The most fillet·s² any of `joints` adds within `ball` of c.
float most_fillet(const Vec3& c, float ball, std::span<const BlendJoint> joints) {
  float fillet = 0;
  for (const BlendJoint& j : joints) {
    const float s = std::max(0.0f, 1.0f - (glm::length(c - j.centre) - ball) / j.reach_m);
    fillet = std::max(fillet, j.fillet_m * std::min(1.0f, s) * std::min(1.0f, s));
  }
  return fillet;
}

// Samples the field at the grid points, block by block (a uniform block's inner points take the
// centre's value; polygonise_box).
Grid sample_grid(FieldRef field_at, const Vec3& lo, const glm::ivec3& cells, float h,
                 std::span<const BlendJoint> joints) {
  Grid g{cells + 2, lo - Vec3(h), h, {}, {}};
  const glm::ivec3 n = g.n;
  g.field.resize(static_cast<size_t>(n.x + 1) * static_cast<size_t>(n.y + 1) * static_cast<size_t>(n.z + 1));
  g.border.resize(g.field.size());
  constexpr int kBlock = 4;
  const float ball = (0.5f * kBlock + 1) * std::sqrt(3.0f) * h;
  for (int bk = 0; bk <= n.z; bk += kBlock)
    for (int bj = 0; bj <= n.y; bj += kBlock)
      for (int bi = 0; bi <= n.x; bi += kBlock) {
        const Vec3 c = g.origin + h * (Vec3(bi, bj, bk) + 0.5f * static_cast<float>(kBlock - 1));
        const float fillet = most_fillet(c, ball, joints);
        const float centre = field_at(c);
        const bool uniform = std::abs(centre) > 1.2f * ball + fillet;
        for (int k = bk; k <= std::min(bk + kBlock - 1, n.z); ++k)
          for (int j = bj; j <= std::min(bj + kBlock - 1, n.y); ++j)
            for (int i = bi; i <= std::min(bi + kBlock - 1, n.x); ++i) {
              const bool outer = i == 0 || j == 0 || k == 0 || i == n.x || j == n.y || k == n.z;
              const bool edge = i == 1 || j == 1 || k == 1 || i == n.x - 1 || j == n.y - 1 || k == n.z - 1;
              g.border[g.index(i, j, k)] = outer;
              g.field[g.index(i, j, k)] = outer ? h : uniform && !edge ? centre : field_at(g.position(i, j, k));
            }
      }
  return g;
}

// The mesh polygonise_box builds, one vertex per grid edge the surface crosses.
struct EdgeVertices {
  const Grid& grid;
  FieldRef field_at;
  FieldRef normal_at;
  TriangleMesh mesh;
  std::unordered_map<uint64_t, uint32_t> edge_vertex;

  // Where along the grid edge a–b (a inside, b outside) the surface lies, 0 at a.
  float crossing(size_t a, size_t b, const Vec3& pa, const Vec3& pb) const {
    float fa = grid.field[a], fb = grid.field[b];
    float ta = 0, tb = 1;
    float t = fa / (fa - fb);
    // Regula falsi (the Illinois variant) along the edge onto the surface, except on edges to
    // the forced-outside border, where the surface is the closing cap.
    if (!grid.border[a] && !grid.border[b]) {
      int side_kept = 0;
      for (int it = 0; it < 16 && fa != fb; ++it) {
        const float ft = field_at(pa + (pb - pa) * t);
        if (std::abs(ft) <= 1e-3f * grid.h) break;  // micrometres: on the surface
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
    return t;
  }

  // The vertex where the surface crosses the grid edge a–b (a inside, b outside).
  uint32_t vertex_on(size_t a, size_t b, const Vec3& pa, const Vec3& pb) {
    const uint64_t key = a < b ? (static_cast<uint64_t>(a) << 32 | b) : (static_cast<uint64_t>(b) << 32 | a);
    if (const auto it = edge_vertex.find(key); it != edge_vertex.end()) return it->second;
    // Not at a grid point: the vertices of the edges meeting there stay apart.
    const float t = std::clamp(crossing(a, b, pa, pb), 1e-3f, 1 - 1e-3f);
    const Vec3 p = pa + (pb - pa) * t;
    const float e = 0.05f * grid.h;
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
  }

  // Adds the triangle a b c, oriented so its normal points away from `inside_point`.
  void emit(uint32_t a, uint32_t b, uint32_t c, const Vec3& inside_point) {
    const Vec3 pa = mesh.positions[a], pb = mesh.positions[b], pc = mesh.positions[c];
    const Vec3 nrm = glm::cross(pb - pa, pc - pa);
    if (glm::dot(nrm, pa - inside_point) < 0) std::swap(b, c);
    mesh.triangles.emplace_back(a, b, c);
  }
};

// One cell's corners: grid indices and positions.
struct Cell {
  std::array<size_t, 8> id;
  std::array<Vec3, 8> pos;
};

// The surface within one tetrahedron of a cell (corners `tet`): a triangle cutting off one
// corner (inside or outside), or a quad between two.
void march_tetrahedron(EdgeVertices& ev, const Cell& cell, const std::array<int, 4>& tet) {
  const Grid& grid = ev.grid;
  std::array<int, 4> in{}, out{};
  int ni = 0, no = 0;
  for (int c : tet) {
    if (grid.field[cell.id[static_cast<size_t>(c)]] < 0)
      in[static_cast<size_t>(ni++)] = c;
    else
      out[static_cast<size_t>(no++)] = c;
  }
  if (ni == 0 || ni == 4) return;
  auto v = [&](int a, int b) {
    return ev.vertex_on(cell.id[static_cast<size_t>(a)], cell.id[static_cast<size_t>(b)],
                        cell.pos[static_cast<size_t>(a)], cell.pos[static_cast<size_t>(b)]);
  };
  const auto& pos = cell.pos;
  if (ni == 1) {
    ev.emit(v(in[0], out[0]), v(in[0], out[1]), v(in[0], out[2]), pos[static_cast<size_t>(in[0])]);
  } else if (ni == 3) {
    ev.emit(
        v(in[0], out[0]), v(in[1], out[0]), v(in[2], out[0]),
        (pos[static_cast<size_t>(in[0])] + pos[static_cast<size_t>(in[1])] + pos[static_cast<size_t>(in[2])]) / 3.0f);
  } else {
    const uint32_t a = v(in[0], out[0]), b = v(in[0], out[1]), c = v(in[1], out[1]), d = v(in[1], out[0]);
    const Vec3 inside_point = (pos[static_cast<size_t>(in[0])] + pos[static_cast<size_t>(in[1])]) * 0.5f;
    ev.emit(a, b, c, inside_point);
    ev.emit(a, c, d, inside_point);
  }
}

// The surface within the cell from grid point (i, j, k): its six tetrahedra around the 0–6
// diagonal.
void march_cell(EdgeVertices& ev, int i, int j, int k) {
  static constexpr std::array<std::array<int, 3>, 8> kCorner = {
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
  static constexpr std::array<std::array<int, 4>, 6> kTet = {
      {{0, 5, 1, 6}, {0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}}};
  const Grid& grid = ev.grid;
  Cell cell;
  int inside = 0;
  for (int c = 0; c < 8; ++c) {
    const auto& o = kCorner[static_cast<size_t>(c)];
    cell.id[static_cast<size_t>(c)] = grid.index(i + o[0], j + o[1], k + o[2]);
    cell.pos[static_cast<size_t>(c)] = grid.position(i + o[0], j + o[1], k + o[2]);
    inside += grid.field[cell.id[static_cast<size_t>(c)]] < 0;
  }
  if (inside == 0 || inside == 8) return;
  for (const auto& tet : kTet) march_tetrahedron(ev, cell, tet);
}

}  // namespace

TriangleMesh polygonise_box(FieldRef field_at, FieldRef normal_at, const Vec3& lo, const glm::ivec3& cells, float h,
                            std::span<const BlendJoint> joints) {
  const Grid grid = sample_grid(field_at, lo, cells, h, joints);
  EdgeVertices ev{grid, field_at, normal_at, {}, {}};
  for (int k = 0; k < grid.n.z; ++k)
    for (int j = 0; j < grid.n.y; ++j)
      for (int i = 0; i < grid.n.x; ++i) march_cell(ev, i, j, k);
  return std::move(ev.mesh);
}

}  // namespace surface_detail

float blended_cones(const Vec3& x, std::span<const BlendCone> cones, const BlendJoint& joint) {
  using namespace surface_detail;  // the internals (surface_detail.h)
  float f1 = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < std::min<size_t>(cones.size(), 16); ++i) {
    const ConeDistance cd = cone_distance(x, cones[i]);
    f1 = std::min(f1, cd.d - cd.r);
  }
  return blend_field(x, cones, f1, joint);
}

TriangleMesh polygonise_joint(std::span<const BlendCone> cones, const BlendJoint& joint, float half_m, int cells) {
  using namespace surface_detail;  // the internals (surface_detail.h)
  const float h = 2 * half_m / static_cast<float>(cells);
  auto field = [&](const Vec3& x) { return blended_cones(x, cones, joint); };
  return polygonise_box(FieldRef(field), FieldRef(field), joint.centre - Vec3(half_m), glm::ivec3(cells), h,
                        std::span(&joint, 1));
}

}  // namespace sylva
