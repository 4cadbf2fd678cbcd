#pragma once
// The light-view pass (Hart & Baker §4.1 "Compute Photosynthesis", §6.1): the scene seen from a
// light direction through an orthographic projection over the crown's bounding square, with a
// z-buffer and an item buffer. Leaf polygons carry the index of the limb they grow on (an item
// ≥ 0); limbs and obstacles are blockers (item −1). The intercepted leaf area of an item is its
// pixel count times the pixel area, so p_i of eq. 14 is in m² of leaf seen from the light.
//
// CPU only, single-threaded and deterministic: triangles are drawn in order, a pixel keeps the
// fragment nearest the light, ties keep the first drawn. Raster space: x right, y down, pixel
// (0, 0) top-left (docs/design.md §4); pixel centres are sampled.

#include "core/math.h"
#include "geometry/mesh.h"

#include <cstdint>
#include <vector>

namespace sylva {

// Triangles to draw, three vertices each in world space (metres), with one item per triangle.
struct LightViewGeometry {
  std::vector<Vec3> vertices;
  std::vector<int32_t> items;

  size_t triangle_count() const { return items.size(); }
  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, int32_t item);
  // Corners in order around the quad.
  void add_quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int32_t item);
  // Every triangle of `mesh` (and its leaf quads, if any) as blockers, placed by world_from_object.
  void add_blockers(const TriangleMesh& mesh, const Mat4& world_from_object);
  void add_blockers(const LeafQuads& leaves, const Mat4& world_from_object);
};

// The rendered view: `items` (−1 where no leaf is seen) and depth along the light direction
// (larger = nearer the light), resolution × resolution, row-major. `pixel_area_m2` is the area a
// pixel covers on a plane facing the light; `window_*` the square's origin and side in the light's
// frame (Frame::from_z(to_light) x and y).
struct LightView {
  int resolution = 0;
  float pixel_area_m2 = 0.0f;
  Vec2 window_origin{0.0f};
  float window_side_m = 0.0f;
  std::vector<int32_t> items;
  std::vector<float> depth;
};

// A fixed window (Hart & Baker §6.1: "the edges of this window form a natural aperture of
// available light such as a tree might receive if growing in a forest clearing"): the square of
// side `side_m` facing the light, centred on the projection of `centre`. side_m ≤ 0: the crown's
// own bounding square.
struct LightWindow {
  Vec3 centre{0.0f};
  float side_m = 0.0f;
};

// Renders `geometry` looking down `-to_light` (`to_light` a unit vector from the scene toward the
// light). The window is `window` when it has a side, else the bounding square of the triangles
// with items ≥ 0 (the crown), widened by 1 %; what lies outside it does not matter. An empty
// crown gives an empty view (resolution 0).
LightView render_light_view(const LightViewGeometry& geometry, const Vec3& to_light, int resolution,
                            const LightWindow& window = {});

// Intercepted area (m²) per item 0..item_count−1: pixels showing the item × pixel area.
std::vector<float> intercepted_area(const LightView& view, size_t item_count);

// Where light comes from over a growing season (Hart & Baker §4.1, footnote 5): the sun's path at
// a latitude over a range of days, and the sky (cosine-weighted), chosen sun:sky as
// sun_weight : 1 − sun_weight (Greene's 80:20 by default).
struct LightDirections {
  float latitude_deg = 45.0f;
  int first_day = 120;  // day of the year, 1..365
  int last_day = 270;
  float sun_weight = 0.8f;
};

// A unit direction toward the light, +Z up, +Y north, +X east. Sun: a day uniform in the season,
// a time of day uniform over daylight accepted with probability sin(elevation) (the sun's
// intensity on a horizontal leaf); the solar declination is Cooper's 23.45°·sin(2π(284 + day)/365).
// Sky: cosine-weighted over the upper hemisphere. Deterministic in `seed`.
Vec3 sample_light_direction(const LightDirections& directions, uint64_t seed);

// The sun's direction at a day of the year and an hour angle (rad, 0 at solar noon, positive in
// the afternoon) at a latitude.
Vec3 sun_direction(float latitude_rad, int day, float hour_angle_rad);

}  // namespace sylva
