#include "geometry/solids/half_space.h"

#include "core/error.h"
#include "core/hash.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace sylva {

namespace {

using DVec3 = glm::dvec3;

// The sphere tracer's smallest step, as a fraction of the solid's bounding-box diagonal: features
// thinner than this may be stepped over.
constexpr double kMinStep = 0x1p-14;
constexpr int kMaxSteps = 4096;
constexpr int kBisections = 24;

double plane_distance(const HalfSpace& hs, const DVec3& p) { return glm::dot(DVec3(hs.normal), p) - hs.offset; }

// clip_ray with every plane pushed out by `grow`.
RaySpan clip_grown(const ConvexPolytope& planes, const Vec3& o, const Vec3& d, double grow) {
  RaySpan span;
  const DVec3 od(o), dd(d);
  for (size_t i = 0; i < planes.size(); ++i) {
    const DVec3 n(planes[i].normal);
    const double denom = glm::dot(n, dd);
    const double num = planes[i].offset + grow - glm::dot(n, od);
    if (denom == 0.0) {
      if (num < 0.0) return RaySpan{1.0, 0.0, -1, -1};
      continue;
    }
    const double t = num / denom;
    if (denom < 0.0) {
      if (t > span.t_entry) {
        span.t_entry = t;
        span.entry_plane = static_cast<int>(i);
      }
    } else if (t < span.t_exit) {
      span.t_exit = t;
      span.exit_plane = static_cast<int>(i);
    }
  }
  return span;
}

struct Polygon {
  std::vector<DVec3> points;
  int plane = -1;
};

// Sorts points lying on the plane with unit normal n counter-clockwise about n.
void sort_around(std::vector<DVec3>& points, const DVec3& n) {
  DVec3 c(0.0);
  for (const DVec3& p : points) c += p;
  c /= static_cast<double>(points.size());
  const DVec3 a = std::abs(n.x) < 0.9 ? DVec3(1, 0, 0) : DVec3(0, 1, 0);
  const DVec3 u = glm::normalize(glm::cross(a, n));
  const DVec3 v = glm::cross(n, u);
  std::vector<std::pair<double, DVec3>> keyed;
  for (const DVec3& p : points) keyed.emplace_back(std::atan2(glm::dot(p - c, v), glm::dot(p - c, u)), p);
  std::sort(keyed.begin(), keyed.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (size_t i = 0; i < points.size(); ++i) points[i] = keyed[i].second;
}

std::vector<Polygon> cube(double e) {
  std::vector<Polygon> out;
  for (int axis = 0; axis < 3; ++axis)
    for (double s : {-1.0, 1.0}) {
      DVec3 n(0.0);
      n[axis] = s;
      Polygon poly;
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      for (const auto& [x, y] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}) {
        DVec3 p(0.0);
        p[axis] = s * e;
        p[a] = x * e;
        p[b] = y * e;
        poly.points.push_back(p);
      }
      sort_around(poly.points, n);
      out.push_back(std::move(poly));
    }
  return out;
}

}  // namespace

float polytope_distance(const ConvexPolytope& planes, const Vec3& p) {
  float f = -std::numeric_limits<float>::infinity();
  for (const HalfSpace& hs : planes) f = std::max(f, glm::dot(hs.normal, p) - hs.offset);
  return f;
}

RaySpan clip_ray(const ConvexPolytope& planes, const Vec3& o, const Vec3& d) { return clip_grown(planes, o, d, 0.0); }

PolytopeFaces polytope_faces(const ConvexPolytope& planes, float extent) {
  const double eps = 1e-9 * extent;
  std::vector<Polygon> polys = cube(extent);
  for (size_t i = 0; i < planes.size() && !polys.empty(); ++i) {
    const HalfSpace& hs = planes[i];
    std::vector<Polygon> kept;
    std::vector<DVec3> cap;
    bool cut = false;
    for (const Polygon& poly : polys) {
      Polygon out;
      out.plane = poly.plane;
      const size_t n = poly.points.size();
      for (size_t k = 0; k < n; ++k) {
        const DVec3& a = poly.points[k];
        const DVec3& b = poly.points[(k + 1) % n];
        const double da = plane_distance(hs, a), db = plane_distance(hs, b);
        if (da <= eps) out.points.push_back(a);
        if (std::abs(da) <= eps) cap.push_back(a);
        if (da > eps) cut = true;
        if ((da < -eps && db > eps) || (da > eps && db < -eps)) {
          const DVec3 x = a + (b - a) * (da / (da - db));
          out.points.push_back(x);
          cap.push_back(x);
        }
      }
      if (out.points.size() >= 3) kept.push_back(std::move(out));
    }
    if (!cut) continue;  // the plane does not cut the current polytope: redundant
    std::vector<DVec3> unique;
    for (const DVec3& p : cap)
      if (std::none_of(unique.begin(), unique.end(), [&](const DVec3& q) { return glm::length(p - q) <= 1e2 * eps; }))
        unique.push_back(p);
    if (unique.size() >= 3) {
      sort_around(unique, DVec3(hs.normal));
      kept.push_back(Polygon{std::move(unique), static_cast<int>(i)});
    }
    polys = std::move(kept);
  }
  PolytopeFaces faces;
  for (Polygon& p : polys) {
    std::vector<Vec3> pts;
    for (const DVec3& q : p.points) pts.emplace_back(q);
    faces.polygons.push_back(std::move(pts));
    faces.plane.push_back(p.plane);
    if (p.plane < 0) faces.bounded = false;
  }
  return faces;
}

double polytope_volume(const PolytopeFaces& faces) {
  double v = 0.0;
  for (const std::vector<Vec3>& poly : faces.polygons)
    for (size_t k = 1; k + 1 < poly.size(); ++k)
      v += glm::dot(DVec3(poly[0]), glm::cross(DVec3(poly[k]), DVec3(poly[k + 1]))) / 6.0;
  return v;
}

TriangleMesh polytope_mesh(const PolytopeFaces& faces) {
  TriangleMesh mesh;
  for (const std::vector<Vec3>& poly : faces.polygons) {
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    Vec3 n(0.0f);
    for (size_t k = 1; k + 1 < poly.size(); ++k) n += glm::cross(poly[k] - poly[0], poly[k + 1] - poly[0]);
    n = glm::normalize(n);
    for (const Vec3& p : poly) {
      mesh.positions.push_back(p);
      mesh.normals.push_back(n);
    }
    for (uint32_t k = 1; k + 1 < poly.size(); ++k) mesh.triangles.emplace_back(base, base + k, base + k + 1);
  }
  return mesh;
}

ConvexPolytope grow_polytope(const ConvexPolytope& planes, float distance) {
  ConvexPolytope out = planes;
  for (HalfSpace& hs : out) hs.offset += distance;
  return out;
}

float solid_lipschitz(const HalfSpaceSolid& solid) {
  return solid.displacement_m > 0.0f ? 1.0f + solid.displacement_m * fbm_lipschitz(solid.displacement) : 1.0f;
}

float solid_distance(const HalfSpaceSolid& solid, const Vec3& p) {
  const float f = polytope_distance(solid.planes, p);
  return solid.displacement_m > 0.0f ? f + solid.displacement_m * fbm(solid.displacement, p) : f;
}

void finish_solid(HalfSpaceSolid& solid, float extent_m) {
  const PolytopeFaces faces = polytope_faces(grow_polytope(solid.planes, solid.displacement_m), extent_m);
  if (faces.polygons.empty()) throw Error("the half-spaces have an empty intersection");
  if (!faces.bounded)
    throw Error(fmt::format("the half-spaces do not enclose a bounded region (within {} m of the origin)", extent_m));
  Bounds3 b;
  for (const auto& poly : faces.polygons)
    for (const Vec3& p : poly) b.extend(p);
  // Pad by a hair so hits exactly on a bounding face are inside the box Embree tests, and by more
  // than polytope_faces' merging distance for near-coincident vertices (1e-7 of the extent).
  const Vec3 pad(1e-5f * glm::length(b.hi - b.lo) + 1e-6f * extent_m);
  solid.bounds = Bounds3{b.lo - pad, b.hi + pad};
  solid.lipschitz = solid_lipschitz(solid);
}

bool intersect_solid(const HalfSpaceSolid& solid, const Vec3& o, const Vec3& d, float t_min, float t_max,
                     SolidHit* hit) {
  if (solid.displacement_m <= 0.0f) {
    const RaySpan span = clip_ray(solid.planes, o, d);
    if (span.empty()) return false;
    if (span.t_entry > t_min && span.t_entry < t_max) {
      *hit = SolidHit{static_cast<float>(span.t_entry), solid.planes[size_t(span.entry_plane)].normal};
      return true;
    }
    if (span.t_exit > t_min && span.t_exit < t_max) {
      *hit = SolidHit{static_cast<float>(span.t_exit), solid.planes[size_t(span.exit_plane)].normal};
      return true;
    }
    return false;
  }
  // Sphere tracing of D inside the grown polytope, which contains the solid.
  const RaySpan span = clip_grown(solid.planes, o, d, solid.displacement_m);
  double t0 = std::max<double>(span.t_entry, t_min), t1 = std::min<double>(span.t_exit, t_max);
  if (!(t0 < t1)) return false;
  const double speed = glm::length(DVec3(d));
  if (!(speed > 0.0)) return false;
  const double size = glm::length(DVec3(solid.bounds.hi - solid.bounds.lo));
  const double min_step = kMinStep * size / speed;
  const auto at = [&](double t) { return solid_distance(solid, Vec3(DVec3(o) + t * DVec3(d))); };
  double t = t0;
  float D = at(t);
  const bool outside = D >= 0.0f;
  for (int step = 0; step < kMaxSteps && t < t1; ++step) {
    const double t_next = std::min(t1, t + std::max(std::abs(D) / (solid.lipschitz * speed), min_step));
    const float D_next = at(t_next);
    if ((D_next >= 0.0f) != outside) {
      double lo = t, hi = t_next;
      for (int k = 0; k < kBisections; ++k) {
        const double mid = 0.5 * (lo + hi);
        ((at(mid) >= 0.0f) == outside ? lo : hi) = mid;
      }
      // lo is on the ray's starting side of the surface (outside for a ray from outside).
      if (!(hi > t_min && lo < t_max)) return false;
      const Vec3 p(DVec3(o) + lo * DVec3(d));
      const float h = static_cast<float>(1e-5 * size);
      const Vec3 g(solid_distance(solid, p + Vec3(h, 0, 0)) - solid_distance(solid, p - Vec3(h, 0, 0)),
                   solid_distance(solid, p + Vec3(0, h, 0)) - solid_distance(solid, p - Vec3(0, h, 0)),
                   solid_distance(solid, p + Vec3(0, 0, h)) - solid_distance(solid, p - Vec3(0, 0, h)));
      const float lg = glm::length(g);
      *hit = SolidHit{static_cast<float>(lo), lg > 0.0f ? g / lg : -glm::normalize(d)};
      return true;
    }
    t = t_next;
    D = D_next;
  }
  return false;
}

uint32_t solid_palette_index(const SolidColouring& colouring, const Vec3& p, uint32_t count) {
  if (count <= 1) return 0;
  if (colouring.kind == SolidColouring::Kind::Cells) {
    const Vec3 c = glm::floor(p / colouring.cell_m);
    const uint64_t h =
        hash_ids(colouring.seed, static_cast<uint64_t>(static_cast<int64_t>(c.x)),
                 static_cast<uint64_t>(static_cast<int64_t>(c.y)), static_cast<uint64_t>(static_cast<int64_t>(c.z)));
    return static_cast<uint32_t>((h >> 32) * count >> 32);
  }
  // fBm is concentrated near 0: the palette spans [−0.5, 0.5], values beyond take the end entries.
  const float v = fbm(colouring.fbm, p);
  return static_cast<uint32_t>(
      std::clamp(static_cast<int>((v + 0.5f) * static_cast<float>(count)), 0, static_cast<int>(count) - 1));
}

}  // namespace sylva
