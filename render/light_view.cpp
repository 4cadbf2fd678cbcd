#include "render/light_view.h"

#include "core/rng.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sylva {

void LightViewGeometry::add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, int32_t item) {
  vertices.push_back(a);
  vertices.push_back(b);
  vertices.push_back(c);
  items.push_back(item);
}

void LightViewGeometry::add_quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int32_t item) {
  add_triangle(a, b, c, item);
  add_triangle(a, c, d, item);
}

void LightViewGeometry::add_blockers(const TriangleMesh& mesh, const Mat4& world_from_object) {
  auto world = [&](uint32_t v) { return Vec3(world_from_object * Vec4(mesh.positions[v], 1.0f)); };
  for (const glm::uvec3& t : mesh.triangles) add_triangle(world(t.x), world(t.y), world(t.z), -1);
}

void LightViewGeometry::add_blockers(const LeafQuads& leaves, const Mat4& world_from_object) {
  auto world = [&](size_t v) { return Vec3(world_from_object * Vec4(leaves.corners[v], 1.0f)); };
  for (size_t i = 0; i < leaves.size(); ++i)
    add_quad(world(4 * i), world(4 * i + 1), world(4 * i + 2), world(4 * i + 3), -1);
}

LightView render_light_view(const LightViewGeometry& geometry, const Vec3& to_light, int resolution,
                            const LightWindow& window) {
  LightView view;
  const Frame frame = Frame::from_z(glm::normalize(to_light));
  const size_t n = geometry.triangle_count();
  std::vector<Vec3> projected(geometry.vertices.size());  // (u, v, depth)
  for (size_t k = 0; k < projected.size(); ++k) projected[k] = frame.to_local(geometry.vertices[k]);

  Vec2 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (size_t t = 0; t < n; ++t) {
    if (geometry.items[t] < 0) continue;
    for (size_t c = 0; c < 3; ++c) {
      lo = glm::min(lo, Vec2(projected[3 * t + c]));
      hi = glm::max(hi, Vec2(projected[3 * t + c]));
    }
  }
  if (!(lo.x <= hi.x) || resolution <= 0) return view;
  const bool fixed = window.side_m > 0.0f;
  const float side = fixed ? window.side_m : std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f}) * 1.01f;
  const Vec2 centre = fixed ? Vec2(frame.to_local(window.centre)) : 0.5f * (lo + hi);
  view.resolution = resolution;
  view.window_side_m = side;
  view.window_origin = centre - Vec2(0.5f * side);
  const float pixel = side / static_cast<float>(resolution);
  view.pixel_area_m2 = pixel * pixel;
  const size_t pixels = static_cast<size_t>(resolution) * static_cast<size_t>(resolution);
  view.items.assign(pixels, -1);
  view.depth.assign(pixels, -std::numeric_limits<float>::infinity());
  std::vector<uint8_t> covered(pixels, 0);

  // Raster coordinates: x = (u − u0)/pixel, y = (v_top − v)/pixel.
  const float v_top = view.window_origin.y + side;
  auto raster = [&](const Vec3& p) { return Vec3((p.x - view.window_origin.x) / pixel, (v_top - p.y) / pixel, p.z); };
  for (size_t t = 0; t < n; ++t) {
    const Vec3 a = raster(projected[3 * t]), b = raster(projected[3 * t + 1]), c = raster(projected[3 * t + 2]);
    const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::abs(area) < 1e-12f) continue;  // edge-on: covers no pixel centre
    const float x0 = std::min({a.x, b.x, c.x}), x1 = std::max({a.x, b.x, c.x});
    const float y0 = std::min({a.y, b.y, c.y}), y1 = std::max({a.y, b.y, c.y});
    const int px0 = std::max(0, static_cast<int>(std::ceil(x0 - 0.5f)));
    const int px1 = std::min(resolution - 1, static_cast<int>(std::floor(x1 - 0.5f)));
    const int py0 = std::max(0, static_cast<int>(std::ceil(y0 - 0.5f)));
    const int py1 = std::min(resolution - 1, static_cast<int>(std::floor(y1 - 0.5f)));
    const float inv = 1.0f / area;
    for (int py = py0; py <= py1; ++py) {
      const float y = static_cast<float>(py) + 0.5f;
      for (int px = px0; px <= px1; ++px) {
        const float x = static_cast<float>(px) + 0.5f;
        // Barycentric weights from the edge functions, normalised by the signed area so either
        // winding works; a centre on an edge belongs to the triangle.
        const float wa = ((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x)) * inv;
        const float wb = ((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x)) * inv;
        const float wc = 1.0f - wa - wb;
        if (wa < 0.0f || wb < 0.0f || wc < 0.0f) continue;
        const float z = wa * a.z + wb * b.z + wc * c.z;
        const size_t k = static_cast<size_t>(py) * static_cast<size_t>(resolution) + static_cast<size_t>(px);
        if (covered[k] && z <= view.depth[k]) continue;
        covered[k] = 1;
        view.depth[k] = z;
        view.items[k] = geometry.items[t];
      }
    }
  }
  return view;
}

std::vector<float> intercepted_area(const LightView& view, size_t item_count) {
  std::vector<uint64_t> count(item_count, 0);
  for (const int32_t item : view.items)
    if (item >= 0 && static_cast<size_t>(item) < item_count) ++count[static_cast<size_t>(item)];
  std::vector<float> area(item_count);
  for (size_t i = 0; i < item_count; ++i)
    area[i] = static_cast<float>(static_cast<double>(count[i]) * view.pixel_area_m2);
  return area;
}

Vec3 sun_direction(float latitude_rad, int day, float hour_angle_rad) {
  const float decl = radians(23.45f) * std::sin(kTwoPi * static_cast<float>(284 + day) / 365.0f);
  const float east = -std::cos(decl) * std::sin(hour_angle_rad);
  const float north =
      std::sin(decl) * std::cos(latitude_rad) - std::cos(decl) * std::cos(hour_angle_rad) * std::sin(latitude_rad);
  const float up =
      std::sin(decl) * std::sin(latitude_rad) + std::cos(decl) * std::cos(hour_angle_rad) * std::cos(latitude_rad);
  return glm::normalize(Vec3(east, north, up));
}

Vec3 sample_light_direction(const LightDirections& d, uint64_t seed) {
  Pcg32 rng(seed);
  if (rng.uniform() < d.sun_weight) {
    const float lat = radians(d.latitude_deg);
    for (int attempt = 0; attempt < 64; ++attempt) {
      const int day = d.first_day + static_cast<int>(rng.uniform() * static_cast<float>(d.last_day - d.first_day + 1));
      const float decl = radians(23.45f) * std::sin(kTwoPi * static_cast<float>(284 + day) / 365.0f);
      // Sunset hour angle: cos h0 = −tan φ tan δ.
      const float cos_h0 = std::clamp(-std::tan(lat) * std::tan(decl), -1.0f, 1.0f);
      const float h0 = std::acos(cos_h0);
      const Vec3 sun = sun_direction(lat, day, (2.0f * rng.uniform() - 1.0f) * h0);
      if (h0 > 0.0f && sun.z > 0.0f && rng.uniform() < sun.z) return sun;
    }
  }
  // Cosine-weighted sky (Malley's method).
  const float u1 = rng.uniform(), u2 = rng.uniform();
  const float r = std::sqrt(u1);
  return glm::normalize(
      Vec3(r * std::cos(kTwoPi * u2), r * std::sin(kTwoPi * u2), std::sqrt(std::max(1e-6f, 1.0f - u1))));
}

}  // namespace sylva
