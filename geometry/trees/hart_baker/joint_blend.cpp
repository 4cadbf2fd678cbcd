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

TriangleMesh polygonise_box(FieldRef field_at, FieldRef normal_at, const Vec3& lo, const glm::ivec3& cells, float h,
                            std::span<const BlendJoint> joints) {
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

}  // namespace surface_detail

using namespace surface_detail;

float blended_cones(const Vec3& x, std::span<const BlendCone> cones, const BlendJoint& joint) {
  float f1 = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < std::min<size_t>(cones.size(), 16); ++i) {
    const ConeDistance cd = cone_distance(x, cones[i]);
    f1 = std::min(f1, cd.d - cd.r);
  }
  return blend_field(x, cones, f1, joint);
}

TriangleMesh polygonise_joint(std::span<const BlendCone> cones, const BlendJoint& joint, float half_m, int cells) {
  const float h = 2 * half_m / static_cast<float>(cells);
  auto field = [&](const Vec3& x) { return blended_cones(x, cones, joint); };
  return polygonise_box(FieldRef(field), FieldRef(field), joint.centre - Vec3(half_m), glm::ivec3(cells), h, std::span(&joint, 1));
}

}  // namespace sylva
