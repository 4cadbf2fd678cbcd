#include "geometry/primitives.h"

#include "core/rng.h"
#include "core/sampling.h"

namespace sylva {

TriangleMesh make_plane(float size_x, float size_y, int tiles) {
  TriangleMesh m;
  tiles = std::max(1, tiles);
  for (int j = 0; j <= tiles; ++j)
    for (int i = 0; i <= tiles; ++i) {
      const float u = static_cast<float>(i) / tiles, v = static_cast<float>(j) / tiles;
      m.positions.emplace_back((u - 0.5f) * size_x, (v - 0.5f) * size_y, 0.0f);
      m.normals.emplace_back(0.0f, 0.0f, 1.0f);
      m.uvs.emplace_back(u * size_x, v * size_y);
    }
  const auto idx = [&](int i, int j) { return static_cast<uint32_t>(j * (tiles + 1) + i); };
  for (int j = 0; j < tiles; ++j)
    for (int i = 0; i < tiles; ++i) {
      m.triangles.emplace_back(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1));
      m.triangles.emplace_back(idx(i, j), idx(i + 1, j + 1), idx(i, j + 1));
    }
  return m;
}

TriangleMesh make_box(const Vec3& size) {
  TriangleMesh m;
  const Vec3 h(0.5f * size.x, 0.5f * size.y, size.z);
  // Each face: normal and two tangent axes (t1 × t2 = n) so corners wind counter-clockwise.
  const Vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const Vec3& n : normals) {
    const Vec3 t1 = std::abs(n.z) > 0 ? Vec3(1, 0, 0) : Vec3(0, 0, 1);
    const Vec3 t2 = glm::cross(n, t1);
    const Vec3 center(n.x * h.x, n.y * h.y, n.z > 0 ? size.z : (n.z < 0 ? 0.0f : 0.5f * size.z));
    const Vec3 e1 = t1 * Vec3(h.x, h.y, 0.5f * size.z), e2 = t2 * Vec3(h.x, h.y, 0.5f * size.z);
    const auto base = static_cast<uint32_t>(m.positions.size());
    const Vec3 corners[4] = {center - e1 - e2, center + e1 - e2, center + e1 + e2, center - e1 + e2};
    const Vec2 uvs[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; ++k) {
      m.positions.push_back(corners[k]);
      m.normals.push_back(n);
      m.uvs.push_back(uvs[k]);
    }
    // Orient so the winding agrees with n.
    if (glm::dot(glm::cross(corners[1] - corners[0], corners[2] - corners[0]), n) > 0) {
      m.triangles.emplace_back(base, base + 1, base + 2);
      m.triangles.emplace_back(base, base + 2, base + 3);
    } else {
      m.triangles.emplace_back(base, base + 2, base + 1);
      m.triangles.emplace_back(base, base + 3, base + 2);
    }
  }
  return m;
}

TriangleMesh make_sphere(float radius, int rings) {
  TriangleMesh m;
  rings = std::max(3, rings);
  const int segs = 2 * rings;
  for (int j = 0; j <= rings; ++j) {
    const float theta = kPi * static_cast<float>(j) / rings;
    for (int i = 0; i <= segs; ++i) {
      const float phi = kTwoPi * static_cast<float>(i) / segs;
      const Vec3 n = spherical_direction(std::sin(theta), std::cos(theta), phi);
      m.positions.push_back(radius * n);
      m.normals.push_back(n);
      m.uvs.emplace_back(static_cast<float>(i) / segs, 1.0f - static_cast<float>(j) / rings);
    }
  }
  const auto idx = [&](int i, int j) { return static_cast<uint32_t>(j * (segs + 1) + i); };
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segs; ++i) {
      if (j != 0) m.triangles.emplace_back(idx(i, j), idx(i, j + 1), idx(i + 1, j));
      if (j != rings - 1) m.triangles.emplace_back(idx(i + 1, j), idx(i, j + 1), idx(i + 1, j + 1));
    }
  return m;
}

TriangleMesh make_cylinder(float radius, float height, int segments) {
  TriangleMesh m;
  segments = std::max(3, segments);
  for (int i = 0; i <= segments; ++i) {
    const float phi = kTwoPi * static_cast<float>(i) / segments;
    const Vec3 n(std::cos(phi), std::sin(phi), 0.0f);
    for (int k = 0; k < 2; ++k) {
      m.positions.push_back(radius * n + Vec3(0, 0, k * height));
      m.normals.push_back(n);
      m.uvs.emplace_back(static_cast<float>(i) / segments, k * height);
    }
  }
  for (int i = 0; i < segments; ++i) {
    const auto a = static_cast<uint32_t>(2 * i);
    m.triangles.emplace_back(a, a + 2, a + 3);
    m.triangles.emplace_back(a, a + 3, a + 1);
  }
  for (int k = 0; k < 2; ++k) {  // caps: a centre vertex and a ring with the cap normal
    const Vec3 n(0, 0, k ? 1.0f : -1.0f);
    const auto centre = static_cast<uint32_t>(m.positions.size());
    m.positions.emplace_back(0.0f, 0.0f, k * height);
    m.normals.push_back(n);
    m.uvs.emplace_back(0.5f, 0.5f);
    for (int i = 0; i <= segments; ++i) {
      const float phi = kTwoPi * static_cast<float>(i) / segments;
      m.positions.emplace_back(radius * std::cos(phi), radius * std::sin(phi), k * height);
      m.normals.push_back(n);
      m.uvs.emplace_back(0.5f + 0.5f * std::cos(phi), 0.5f + 0.5f * std::sin(phi));
    }
    for (int i = 0; i < segments; ++i) {
      const uint32_t a = centre + 1 + i;
      if (k)
        m.triangles.emplace_back(centre, a, a + 1);
      else
        m.triangles.emplace_back(centre, a + 1, a);
    }
  }
  return m;
}

LeafQuads make_leaf_cloud(const LeafCloudParams& params, uint64_t seed) {
  LeafQuads leaves;
  leaves.corners.reserve(4 * static_cast<size_t>(params.count));
  leaves.shapes.reserve(params.count);
  for (int i = 0; i < params.count; ++i) {
    Pcg32 rng(hash_ids(seed, static_cast<uint64_t>(i)));
    Vec3 c;
    do {
      c = symmetric3(rng);
    } while (glm::dot(c, c) > 1.0f);
    c *= params.radii;
    const Vec3 normal = sample_uniform_sphere(uniform2(rng));
    const Frame f = Frame::from_z(normal);
    const float spin = kTwoPi * rng.uniform();
    const Vec3 along = std::cos(spin) * f.x + std::sin(spin) * f.y;  // petiole → tip
    const Vec3 across = glm::cross(along, normal);                   // so across × along = normal: CCW seen from above
    const Vec3 half_w = 0.5f * params.leaf_width_m * across;
    const Vec3 base = c - 0.5f * params.leaf_length_m * along;
    const Vec3 tip = c + 0.5f * params.leaf_length_m * along;
    leaves.corners.insert(leaves.corners.end(), {base - half_w, base + half_w, tip + half_w, tip - half_w});
    leaves.shapes.push_back(params.shape);
  }
  return leaves;
}

}  // namespace sylva
