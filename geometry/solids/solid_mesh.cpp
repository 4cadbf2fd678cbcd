#include "geometry/solids/solid_mesh.h"

#include <array>
#include <cmath>
#include <unordered_map>

namespace sylva {

namespace {

// The six tetrahedra of a cube around its 0–7 diagonal; corner bits are x = 1, y = 2, z = 4.
constexpr std::array<std::array<int, 4>, 6> kTets = {
    {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};

}  // namespace

TriangleMesh solid_surface_mesh(const HalfSpaceSolid& solid, int cells) {
  if (solid.displacement_m <= 0.0f) return polytope_mesh(polytope_faces(solid.planes, kSolidExtentM));
  const Vec3 extent = solid.bounds.hi - solid.bounds.lo;
  const float h = std::max({extent.x, extent.y, extent.z}) / static_cast<float>(cells);
  const int nx = static_cast<int>(std::ceil(extent.x / h)) + 1, ny = static_cast<int>(std::ceil(extent.y / h)) + 1,
            nz = static_cast<int>(std::ceil(extent.z / h)) + 1;
  const auto index = [&](int x, int y, int z) { return (static_cast<size_t>(z) * ny + y) * nx + x; };
  const auto point = [&](size_t i) {
    const int x = static_cast<int>(i % nx), y = static_cast<int>(i / nx % ny), z = static_cast<int>(i / nx / ny);
    return solid.bounds.lo + h * Vec3(x, y, z);
  };
  std::vector<float> field(static_cast<size_t>(nx) * ny * nz);
  for (size_t i = 0; i < field.size(); ++i) field[i] = solid_distance(solid, point(i));

  TriangleMesh mesh;
  std::unordered_map<uint64_t, uint32_t> edge_vertex;
  const auto vertex = [&](size_t a, size_t b) {
    if (a > b) std::swap(a, b);
    const uint64_t key = static_cast<uint64_t>(a) * field.size() + b;
    auto it = edge_vertex.find(key);
    if (it != edge_vertex.end()) return it->second;
    const float fa = field[a], fb = field[b];
    const Vec3 p = point(a) + (point(b) - point(a)) * (fa / (fa - fb));
    mesh.positions.push_back(p);
    return edge_vertex[key] = static_cast<uint32_t>(mesh.positions.size() - 1);
  };
  const auto emit = [&](uint32_t a, uint32_t b, uint32_t c, const Vec3& outward) {
    const Vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    if (glm::dot(n, outward) >= 0.0f) {
      mesh.triangles.emplace_back(a, b, c);
    } else {
      mesh.triangles.emplace_back(a, c, b);
    }
  };
  for (int z = 0; z + 1 < nz; ++z)
    for (int y = 0; y + 1 < ny; ++y)
      for (int x = 0; x + 1 < nx; ++x) {
        size_t corner[8];
        for (int c = 0; c < 8; ++c) corner[c] = index(x + (c & 1), y + (c >> 1 & 1), z + (c >> 2 & 1));
        for (const auto& tet : kTets) {
          size_t in[4], out[4];
          int ni = 0, no = 0;
          for (const int c : tet) (field[corner[c]] < 0.0f ? in[ni++] : out[no++]) = corner[c];
          if (ni == 0 || no == 0) continue;
          Vec3 ci(0.0f), co(0.0f);
          for (int k = 0; k < ni; ++k) ci += point(in[k]) / static_cast<float>(ni);
          for (int k = 0; k < no; ++k) co += point(out[k]) / static_cast<float>(no);
          const Vec3 outward = co - ci;
          if (ni == 1 || no == 1) {
            const size_t apex = ni == 1 ? in[0] : out[0];
            const size_t* others = ni == 1 ? out : in;
            emit(vertex(apex, others[0]), vertex(apex, others[1]), vertex(apex, others[2]), outward);
          } else {
            const uint32_t a = vertex(in[0], out[0]), b = vertex(in[0], out[1]), c = vertex(in[1], out[1]),
                           d = vertex(in[1], out[0]);
            emit(a, b, c, outward);
            emit(a, c, d, outward);
          }
        }
      }
  mesh.normals.assign(mesh.positions.size(), Vec3(0.0f));
  for (const glm::uvec3& t : mesh.triangles) {
    const Vec3 n = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
    mesh.normals[t.x] += n;
    mesh.normals[t.y] += n;
    mesh.normals[t.z] += n;
  }
  for (Vec3& n : mesh.normals) {
    const float l = glm::length(n);
    n = l > 0.0f ? n / l : Vec3(0, 0, 1);
  }
  return mesh;
}

}  // namespace sylva
