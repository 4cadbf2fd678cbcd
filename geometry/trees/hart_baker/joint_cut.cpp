// Opening a Hart–Baker joint where a limb leaves it, and zipping the opening to the limb's tube
// (docs/hart_baker.md "Blended joints").

#include "geometry/trees/hart_baker/surface_detail.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>

namespace sylva::surface_detail {

namespace {

// A field's gradient by central differences (not divided by the step).
Vec3 field_gradient(FieldRef f, const Vec3& p, float e) {
  return Vec3(f(p + Vec3(e, 0, 0)) - f(p - Vec3(e, 0, 0)), f(p + Vec3(0, e, 0)) - f(p - Vec3(0, e, 0)),
              f(p + Vec3(0, 0, e)) - f(p - Vec3(0, 0, e)));
}

// The angle of p about the axis through `centre` along unit `axis`, in [0, 2π), from `e0`.
float angle_about(const Vec3& p, const Vec3& centre, const Vec3& axis, const Vec3& e0) {
  const Vec3 d = p - centre;
  return wrap(std::atan2(glm::dot(d, glm::cross(axis, e0)), glm::dot(d, e0)));
}

// The vertices' side of a cut's plane: their distance beyond it and their state.
struct CutSides {
  std::vector<float> d;
  std::vector<uint8_t> state;  // 0 kept, 1 removed (beyond, in the cylinder), 2 beyond but outside
};

// Places the cut's plane: a vertex (nearly) on the plane would leave crossings (nearly) on top of
// it, so the plane moves out a little until none is within a thousandth of a cell. Empty when
// eight moves do not clear it.
std::optional<CutSides> place_cut_plane(const TriangleMesh& mesh, JointCut& cut, float cell) {
  const Vec3 u = cut.normal;
  const size_t nv = mesh.positions.size();
  CutSides sides{std::vector<float>(nv), std::vector<uint8_t>(nv)};
  std::vector<float>& d = sides.d;
  for (int attempt = 0;; ++attempt) {
    float nearest = std::numeric_limits<float>::infinity();
    for (size_t v = 0; v < nv; ++v) {
      const Vec3 rel = mesh.positions[v] - cut.origin;
      d[v] = glm::dot(rel, u);
      nearest = std::min(nearest, std::abs(d[v]) < cut.radius_m + cell ? std::abs(d[v]) : nearest);
      sides.state[v] = d[v] <= 0 ? 0 : glm::length(rel - u * d[v]) < cut.radius_m ? 1 : 2;
    }
    if (nearest >= 1e-3f * cell) break;
    if (attempt == 8) return std::nullopt;
    cut.origin += u * (2e-3f * cell);
    cut.gap_m -= 2e-3f * cell;
  }
  return sides;
}

// The joint mesh cut at the plane: the kept triangles, those crossing the plane split there, and
// the new vertices on the plane with the loop's directed edges between them.
struct CutMesh {
  TriangleMesh mesh;
  std::unordered_map<uint64_t, uint32_t> crossing;
  std::unordered_map<uint32_t, uint32_t> next;
};

// Cuts the mesh at the plane of `sides`; empty when a triangle beyond the plane reaches outside
// the cylinder or two crossings start at one vertex.
std::optional<CutMesh> cut_triangles(const TriangleMesh& mesh, const CutSides& sides) {
  const std::vector<float>& d = sides.d;
  const std::vector<uint8_t>& state = sides.state;
  CutMesh cm;
  TriangleMesh& out = cm.mesh;
  out.positions = mesh.positions;
  out.normals = mesh.normals;
  out.uvs = mesh.uvs;
  auto cross = [&](uint32_t a, uint32_t b) {
    const uint64_t key = static_cast<uint64_t>(a) << 32 | b;  // a kept, b removed
    if (const auto it = cm.crossing.find(key); it != cm.crossing.end()) return it->second;
    const float t = d[a] / (d[a] - d[b]);
    const uint32_t v = static_cast<uint32_t>(out.positions.size());
    out.positions.push_back(out.positions[a] + (out.positions[b] - out.positions[a]) * t);
    out.normals.push_back(out.normals[a]);
    out.uvs.emplace_back(0.0f, 0.0f);
    cm.crossing.emplace(key, v);
    return v;
  };
  for (const glm::uvec3& t : mesh.triangles) {
    const int removed = (state[t.x] == 1) + (state[t.y] == 1) + (state[t.z] == 1);
    if (removed == 0) {
      out.triangles.push_back(t);
      continue;
    }
    if (removed == 3) continue;
    if (state[t.x] == 2 || state[t.y] == 2 || state[t.z] == 2) return std::nullopt;
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
    if (!cm.next.emplace(leave, enter).second) return std::nullopt;
    out.triangles.emplace_back(poly[0], poly[1], poly[2]);
    if (n == 4) out.triangles.emplace_back(poly[0], poly[2], poly[3]);
  }
  return cm;
}

// The one loop through every new vertex, in order; empty when they do not make one loop.
std::optional<std::vector<uint32_t>> trace_loop(const CutMesh& cm) {
  const auto& next = cm.next;
  if (next.size() != cm.crossing.size() || next.size() < 3) return std::nullopt;
  std::vector<uint32_t> loop;
  for (uint32_t v = next.begin()->first;;) {
    loop.push_back(v);
    const auto it = next.find(v);
    if (it == next.end()) return std::nullopt;
    v = it->second;
    if (v == loop.front()) break;
    if (loop.size() > next.size()) return std::nullopt;
  }
  if (loop.size() != next.size()) return std::nullopt;
  return loop;
}

// The radius within a cell either side of r0 where the field along axis + dir·r is zero
// (Illinois regula falsi); empty when the field does not change sign there.
std::optional<float> zero_along(FieldRef field, const Vec3& axis, const Vec3& dir, float r0, float cell) {
  float lo = std::max(0.0f, r0 - cell), hi = r0 + cell;
  float flo = field(axis + dir * lo), fhi = field(axis + dir * hi);
  if (flo >= 0 || fhi <= 0) return std::nullopt;
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
  return r;
}

// Moves the loop's vertices onto the zero set, along the plane's radius through each, and gives
// them the gradient of `normal_at` as normal; false when one does not land within a cell.
bool loop_onto_surface(TriangleMesh& out, const std::vector<uint32_t>& loop, const JointCut& cut, FieldRef field,
                       FieldRef normal_at, float cell) {
  const Vec3 u = cut.normal;
  const float e = 0.05f * cell;
  for (const uint32_t v : loop) {
    const Vec3 p = out.positions[v];
    const Vec3 q = (p - cut.origin) - u * glm::dot(p - cut.origin, u);
    const float r0 = glm::length(q);
    if (r0 <= 0) return false;
    const Vec3 axis = p - q, dir = q / r0;
    const std::optional<float> r = zero_along(field, axis, dir, r0, cell);
    if (!r) return false;
    const Vec3 x = axis + dir * *r;
    if (glm::length(x - p) > cell || *r >= cut.radius_m) return false;
    out.positions[v] = x;
    const Vec3 g = field_gradient(normal_at, x, e);
    out.normals[v] = glm::length(g) > 0 ? glm::normalize(g) : out.normals[v];
  }
  return true;
}

// Crossings of a sliver may land on (nearly) the same point: each such loop edge collapses, its
// triangle with it. False when fewer than three loop vertices are left.
bool collapse_slivers(TriangleMesh& out, std::vector<uint32_t>& loop, float cell) {
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
  return true;
}

// Whether the loop goes once around the axis, in one direction (a vertex may fall back a little
// where marching tetrahedra left two crossings close together; the band's walk tolerates that).
bool turns_once(const TriangleMesh& out, const std::vector<uint32_t>& loop, const JointCut& cut) {
  const Vec3 u = cut.normal;
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
  return true;
}

}  // namespace

bool open_joint(TriangleMesh& mesh, JointCut& cut, FieldRef field, FieldRef normal_at, float cell) {
  const std::optional<CutSides> sides = place_cut_plane(mesh, cut, cell);
  if (!sides) return false;
  std::optional<CutMesh> cm = cut_triangles(mesh, *sides);
  if (!cm) return false;
  std::optional<std::vector<uint32_t>> loop = trace_loop(*cm);
  if (!loop) return false;
  TriangleMesh& out = cm->mesh;
  if (!loop_onto_surface(out, *loop, cut, field, normal_at, cell)) return false;
  if (!collapse_slivers(out, *loop, cell)) return false;
  if (!turns_once(out, *loop, cut)) return false;
  cut.loop = std::move(*loop);
  mesh = std::move(out);
  return true;
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

}  // namespace sylva::surface_detail
