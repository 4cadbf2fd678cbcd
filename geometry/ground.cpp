#include "geometry/ground.h"

#include <glm/mat4x4.hpp>

namespace sylva {

namespace {

// The parameter t of the line o + t·d where it meets triangle (a, b, c), edges included; nullopt
// if it misses or runs parallel to the triangle's plane (Möller & Trumbore 1997, without the
// t ≥ 0 restriction).
std::optional<double> line_triangle(const DVec3& o, const DVec3& d, const DVec3& a, const DVec3& b, const DVec3& c) {
  const DVec3 e1 = b - a, e2 = c - a;
  const DVec3 p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (det == 0.0) return std::nullopt;
  const double inv = 1.0 / det;
  const DVec3 s = o - a;
  const double u = glm::dot(s, p) * inv;
  if (u < 0.0 || u > 1.0) return std::nullopt;
  const DVec3 q = glm::cross(s, e1);
  const double v = glm::dot(d, q) * inv;
  if (v < 0.0 || u + v > 1.0) return std::nullopt;
  return glm::dot(e2, q) * inv;
}

}  // namespace

Bounds3 placed_bounds(const TriangleMesh& mesh, const Mat4& world_from_object) {
  Bounds3 object;
  for (const Vec3& p : mesh.positions) object.extend(p);
  return transformed(object, world_from_object);
}

std::optional<float> highest_surface_z(const std::vector<PlacedMesh>& meshes, Vec2 xy) {
  std::optional<double> best;
  for (const PlacedMesh& m : meshes) {
    const Bounds3& b = m.world_bounds;
    if (b.empty() || xy.x < b.lo.x || xy.x > b.hi.x || xy.y < b.lo.y || xy.y > b.hi.y) continue;
    // The world line (x, y, t) in object space: o + t·d, with the same t (the world z).
    const glm::dmat4 object_from_world = glm::inverse(glm::dmat4(m.world_from_object));
    const DVec3 o(object_from_world * glm::dvec4(xy.x, xy.y, 0.0, 1.0));
    const DVec3 d(object_from_world * glm::dvec4(0.0, 0.0, 1.0, 0.0));
    const std::vector<Vec3>& v = m.mesh->positions;
    for (const glm::uvec3& t : m.mesh->triangles) {
      const std::optional<double> hit = line_triangle(o, d, DVec3(v[t.x]), DVec3(v[t.y]), DVec3(v[t.z]));
      if (hit && (!best || *hit > *best)) best = hit;
    }
  }
  if (!best) return std::nullopt;
  return static_cast<float>(*best);
}

}  // namespace sylva
