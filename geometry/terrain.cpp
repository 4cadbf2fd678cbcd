#include "geometry/terrain.h"

#include "core/error.h"
#include "core/hash.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sylva {

TriangleMesh make_terrain_mesh(const HeightField& field) {
  if (field.width < 2 || field.height < 2) throw Error("a terrain needs at least 2 x 2 height samples");
  TriangleMesh mesh;
  const int w = field.width, h = field.height;
  mesh.positions.reserve(static_cast<size_t>(w) * h);
  mesh.normals.reserve(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      mesh.positions.emplace_back(field.min_m.x + static_cast<float>(i) * field.spacing_m.x,
                                  field.min_m.y + static_cast<float>(j) * field.spacing_m.y, field.at(i, j));
      // Central differences (one-sided at the edges): the gradient of the smooth surface the
      // samples come from.
      const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, w - 1);
      const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, h - 1);
      const float dzdx = (field.at(i1, j) - field.at(i0, j)) / (static_cast<float>(i1 - i0) * field.spacing_m.x);
      const float dzdy = (field.at(i, j1) - field.at(i, j0)) / (static_cast<float>(j1 - j0) * field.spacing_m.y);
      mesh.normals.push_back(glm::normalize(Vec3(-dzdx, -dzdy, 1.0f)));
    }
  mesh.triangles.reserve(2 * static_cast<size_t>(w - 1) * (h - 1));
  for (int j = 0; j + 1 < h; ++j)
    for (int i = 0; i + 1 < w; ++i) {
      const auto node = [w](int a, int b) { return static_cast<uint32_t>(b * w + a); };
      const uint32_t n00 = node(i, j), n10 = node(i + 1, j), n11 = node(i + 1, j + 1), n01 = node(i, j + 1);
      mesh.triangles.emplace_back(n00, n10, n11);  // below the diagonal (u >= v)
      mesh.triangles.emplace_back(n00, n11, n01);  // above it
    }
  return mesh;
}

float terrain_height(const HeightField& field, Vec2 xy) {
  const Vec2 g = (xy - field.min_m) / field.spacing_m;
  const float gx = std::clamp(g.x, 0.0f, static_cast<float>(field.width - 1));
  const float gy = std::clamp(g.y, 0.0f, static_cast<float>(field.height - 1));
  const int i = std::min(static_cast<int>(gx), field.width - 2);
  const int j = std::min(static_cast<int>(gy), field.height - 2);
  const float u = gx - static_cast<float>(i), v = gy - static_cast<float>(j);
  const float z00 = field.at(i, j), z10 = field.at(i + 1, j), z11 = field.at(i + 1, j + 1), z01 = field.at(i, j + 1);
  // The two triangles of make_terrain_mesh: (00, 10, 11) where u >= v, (00, 11, 01) elsewhere.
  if (u >= v) return z00 + u * (z10 - z00) + v * (z11 - z10);
  return z00 + v * (z01 - z00) + u * (z11 - z01);
}

float terrain_min_height(const HeightField& field, Vec2 centre, float radius_m) {
  float lowest = terrain_height(field, centre);
  if (!(radius_m > 0.0f)) return lowest;
  // A linear function over the convex region (disc ∩ triangle) takes its minimum at an extreme
  // point of the region: a triangle corner inside the disc, a crossing of a triangle edge with the
  // rim, or the rim point against the triangle's gradient if that lies in the triangle. Every
  // candidate is evaluated on the surface (points beyond the grid are clamped to its edge).
  // Rim points are computed in world coordinates, so they may land a few ulps (of the coordinates,
  // not of the radius) outside the disc: 0.1 mm of slack keeps them.
  const auto consider = [&](Vec2 p) {
    if (glm::length(p - centre) <= radius_m + 1e-4f) lowest = std::min(lowest, terrain_height(field, p));
  };
  const Vec2 lo = (centre - Vec2(radius_m) - field.min_m) / field.spacing_m;
  const Vec2 hi = (centre + Vec2(radius_m) - field.min_m) / field.spacing_m;
  const int i0 = std::clamp(static_cast<int>(std::floor(lo.x)), 0, field.width - 2);
  const int i1 = std::clamp(static_cast<int>(std::floor(hi.x)), 0, field.width - 2);
  const int j0 = std::clamp(static_cast<int>(std::floor(lo.y)), 0, field.height - 2);
  const int j1 = std::clamp(static_cast<int>(std::floor(hi.y)), 0, field.height - 2);
  const auto node = [&](int i, int j) {
    return Vec3(field.min_m + field.spacing_m * Vec2(static_cast<float>(i), static_cast<float>(j)), field.at(i, j));
  };
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const Vec3 n00 = node(i, j), n10 = node(i + 1, j), n11 = node(i + 1, j + 1), n01 = node(i, j + 1);
      for (const auto& tri : {std::array<Vec3, 3>{n00, n10, n11}, std::array<Vec3, 3>{n00, n11, n01}}) {
        for (int e = 0; e < 3; ++e) {
          const Vec2 a(tri[e]), b(tri[(e + 1) % 3]);
          consider(a);
          // Edge a + t·(b − a), t in [0, 1], crossing the circle |p − centre| = r.
          const Vec2 d = b - a, f = a - centre;
          const float qa = glm::dot(d, d), qb = 2.0f * glm::dot(f, d), qc = glm::dot(f, f) - radius_m * radius_m;
          const float disc = qb * qb - 4.0f * qa * qc;
          if (disc < 0.0f) continue;
          for (const float sign : {-1.0f, 1.0f}) {
            const float t = (-qb + sign * std::sqrt(disc)) / (2.0f * qa);
            if (t >= 0.0f && t <= 1.0f) consider(a + t * d);
          }
        }
        const Vec3 normal = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
        const Vec2 gradient = -Vec2(normal) / normal.z;
        const float g = glm::length(gradient);
        if (g <= 0.0f) continue;
        const Vec2 p = centre - radius_m * gradient / g;
        // Inside the triangle (its xy-projection, counter-clockwise)?
        bool inside = true;
        for (int e = 0; e < 3; ++e) {
          const Vec2 a(tri[e]), b(tri[(e + 1) % 3]);
          inside = inside && (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) >= 0.0f;
        }
        if (inside) consider(p);
      }
    }
  return lowest;
}

HeightField resample_height_raster(const std::vector<float>& values, int width, int height, Vec2 min_m, float pixel_m,
                                   int step) {
  if (width < 2 || height < 2) throw Error("a terrain raster needs at least 2 x 2 pixels");
  if (values.size() != static_cast<size_t>(width) * static_cast<size_t>(height))
    throw Error("a terrain raster needs one height per pixel");
  step = std::max(step, 1);
  HeightField f;
  f.width = (width - 1 + step - 1) / step + 1;
  f.height = (height - 1 + step - 1) / step + 1;
  f.min_m = min_m;
  f.spacing_m = Vec2(pixel_m * static_cast<float>(width - 1) / static_cast<float>(f.width - 1),
                     pixel_m * static_cast<float>(height - 1) / static_cast<float>(f.height - 1));
  f.heights.resize(static_cast<size_t>(f.width) * static_cast<size_t>(f.height));
  // Pixel (x, y) of the raster is node (x, height − 1 − y) of the full-resolution grid.
  const auto pixel = [&](int x, int y_south) {
    return values[static_cast<size_t>(height - 1 - y_south) * static_cast<size_t>(width) + static_cast<size_t>(x)];
  };
  for (int j = 0; j < f.height; ++j)
    for (int i = 0; i < f.width; ++i) {
      // Exact integer positions for every node when step divides the raster; bilinear otherwise.
      const double px = static_cast<double>(i) * (width - 1) / (f.width - 1);
      const double py = static_cast<double>(j) * (height - 1) / (f.height - 1);
      const int x0 = std::min(static_cast<int>(px), width - 2), y0 = std::min(static_cast<int>(py), height - 2);
      const float u = static_cast<float>(px - x0), v = static_cast<float>(py - y0);
      const float z = (1 - u) * (1 - v) * pixel(x0, y0) + u * (1 - v) * pixel(x0 + 1, y0) +
                      (1 - u) * v * pixel(x0, y0 + 1) + u * v * pixel(x0 + 1, y0 + 1);
      f.heights[static_cast<size_t>(j) * static_cast<size_t>(f.width) + static_cast<size_t>(i)] = z;
    }
  return f;
}

float value_noise(uint64_t seed, Vec2 p) {
  const float fx = std::floor(p.x), fy = std::floor(p.y);
  const auto ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  const auto lattice = [seed](int64_t x, int64_t y) {
    return static_cast<float>(hash_ids(seed, static_cast<uint64_t>(x), static_cast<uint64_t>(y)) >> 40) * 0x1p-23f -
           1.0f;
  };
  const auto fade = [](float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); };
  const float u = fade(p.x - fx), v = fade(p.y - fy);
  const float a = lattice(ix, iy) + u * (lattice(ix + 1, iy) - lattice(ix, iy));
  const float b = lattice(ix, iy + 1) + u * (lattice(ix + 1, iy + 1) - lattice(ix, iy + 1));
  return a + v * (b - a);
}

HeightField make_procedural_terrain(const ProceduralTerrainParams& params) {
  HeightField f;
  f.width = std::max(2, static_cast<int>(std::ceil(params.size_m.x / params.resolution_m)) + 1);
  f.height = std::max(2, static_cast<int>(std::ceil(params.size_m.y / params.resolution_m)) + 1);
  f.spacing_m = params.size_m / Vec2(static_cast<float>(f.width - 1), static_cast<float>(f.height - 1));
  f.min_m = params.centre_m - 0.5f * params.size_m;
  f.heights.resize(static_cast<size_t>(f.width) * static_cast<size_t>(f.height));
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int j = 0; j < f.height; ++j)
    for (int i = 0; i < f.width; ++i) {
      // World position in units of the first octave's wavelength: the terrain does not depend on
      // the resolution it is sampled at.
      const Vec2 p =
          (f.min_m + f.spacing_m * Vec2(static_cast<float>(i), static_cast<float>(j))) / params.feature_size_m;
      float z = 0.0f, amplitude = 1.0f, frequency = 1.0f;
      for (int o = 0; o < params.octaves; ++o) {
        const float n = value_noise(hash_ids(params.seed, 0x7E44, o), p * frequency);
        z += amplitude * (params.ridged ? 1.0f - std::abs(n) : n);
        amplitude *= params.gain;
        frequency *= 2.0f;
      }
      f.heights[static_cast<size_t>(j) * static_cast<size_t>(f.width) + static_cast<size_t>(i)] = z;
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
  const float scale = hi > lo ? params.relief_m / (hi - lo) : 0.0f;
  for (float& z : f.heights) z = (z - lo) * scale;
  return f;
}

}  // namespace sylva
