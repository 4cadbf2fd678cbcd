// The light-view pass (render/light_view.h, Hart & Baker §4.1): projected leaf areas, occlusion,
// exact item indices, invariance under rotation about the light axis, and the light directions.

#include "core/hash.h"
#include "core/rng.h"
#include "render/light_view.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <set>

namespace sylva {
namespace {

// A square of side s centred at c in the plane with unit normal n, turned by `spin` about n.
void add_square(LightViewGeometry& g, Vec3 c, Vec3 n, float s, float spin, int32_t item) {
  const Frame f = Frame::from_z(glm::normalize(n));
  const Vec3 a = (std::cos(spin) * f.x + std::sin(spin) * f.y) * (0.5f * s);
  const Vec3 b = (-std::sin(spin) * f.x + std::cos(spin) * f.y) * (0.5f * s);
  g.add_quad(c - a - b, c + a - b, c + a + b, c - a + b, item);
}

TEST(LightView, SquareLeafCoversItsProjectedArea) {
  for (const float tilt_deg : {0.0f, 40.0f}) {
    LightViewGeometry g;
    add_square(g, Vec3(0, 0, 1), Vec3(0, 0, 1), 1.0f, radians(30.0f), 0);
    add_square(g, Vec3(1.6f, 1.1f, 1), Vec3(0, 0, 1), 0.05f, 0.0f, 1);  // widens the window
    const Vec3 light(std::sin(radians(tilt_deg)), 0.0f, std::cos(radians(tilt_deg)));
    const LightView view = render_light_view(g, light, 512);
    ASSERT_EQ(view.resolution, 512);
    const std::vector<float> area = intercepted_area(view, 2);
    const float expected = std::cos(radians(tilt_deg));
    EXPECT_NEAR(area[0], expected, 0.01f * expected) << "tilt " << tilt_deg;
    EXPECT_NEAR(area[1], 0.0025f * expected, 0.2f * 0.0025f);
  }
}

// §6.1's fixed window: the same leaf gives the same area in any window that holds it (only the
// pixel size changes), the window sits on the projection of its centre, and what lies outside the
// window is not seen (the aperture clips it).
TEST(LightView, FixedWindowIsAnAperture) {
  LightViewGeometry g;
  add_square(g, Vec3(1, 0, 2), Vec3(0, 0, 1), 1.0f, 0.0f, 0);
  add_square(g, Vec3(6, 0, 2), Vec3(0, 0, 1), 1.0f, 0.0f, 1);  // outside a 4 m window about the origin
  for (const float side : {4.0f, 8.0f}) {
    const LightView view = render_light_view(g, Vec3(0, 0, 1), 512, LightWindow{Vec3(0, 0, 5), side});
    ASSERT_EQ(view.resolution, 512);
    EXPECT_FLOAT_EQ(view.window_side_m, side);
    EXPECT_NEAR(view.window_origin.x + 0.5f * side, 0.0f, 1e-5f);
    const std::vector<float> area = intercepted_area(view, 2);
    EXPECT_NEAR(area[0], 1.0f, 0.01f) << side;
    EXPECT_EQ(area[1], 0.0f) << side;
  }
  // Seen along a slant, the window's centre is the projection of the given point.
  const Vec3 light = glm::normalize(Vec3(1, 0, 1));
  const LightView slant = render_light_view(g, light, 64, LightWindow{Vec3(0, 0, 3), 10.0f});
  const Vec3 centre = Frame::from_z(light).to_local(Vec3(0, 0, 3));
  EXPECT_NEAR(slant.window_origin.x + 5.0f, centre.x, 1e-5f);
  EXPECT_NEAR(slant.window_origin.y + 5.0f, centre.y, 1e-5f);
  // The crown's own square (no side) still holds both leaves.
  const std::vector<float> own = intercepted_area(render_light_view(g, Vec3(0, 0, 1), 1024), 2);
  EXPECT_NEAR(own[1], 1.0f, 0.01f);
}

TEST(LightView, OccludedLeavesGetNothing) {
  LightViewGeometry g;
  add_square(g, Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0f, 0.0f, 0);     // under the blocker
  add_square(g, Vec3(3, 0, 0), Vec3(0, 0, 1), 1.0f, 0.0f, 1);     // in the open
  add_square(g, Vec3(0, 0, 2), Vec3(0, 0, 1), 1.5f, 0.3f, -1);    // a blocker above leaf 0
  add_square(g, Vec3(3.5f, 0, 1), Vec3(0, 0, 1), 1.0f, 0.0f, 2);  // covers half of leaf 1
  const LightView view = render_light_view(g, Vec3(0, 0, 1), 400);
  const std::vector<float> area = intercepted_area(view, 3);
  EXPECT_EQ(area[0], 0.0f);
  EXPECT_NEAR(area[1], 0.5f, 0.01f);
  EXPECT_NEAR(area[2], 1.0f, 0.01f);
  // Drawing order does not matter: the blocker first gives the same view.
  LightViewGeometry h;
  add_square(h, Vec3(0, 0, 2), Vec3(0, 0, 1), 1.5f, 0.3f, -1);
  add_square(h, Vec3(3.5f, 0, 1), Vec3(0, 0, 1), 1.0f, 0.0f, 2);
  add_square(h, Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0f, 0.0f, 0);
  add_square(h, Vec3(3, 0, 0), Vec3(0, 0, 1), 1.0f, 0.0f, 1);
  EXPECT_EQ(render_light_view(h, Vec3(0, 0, 1), 400).items, view.items);
}

TEST(LightView, ItemIndicesAreExact) {
  LightViewGeometry g;
  const int32_t ids[] = {3, 7, 11, 1000};
  for (int k = 0; k < 4; ++k) add_square(g, Vec3(1.5f * k, 0.7f * k, 0.1f * k), Vec3(0, 0, 1), 0.8f, 0.2f * k, ids[k]);
  const LightView view = render_light_view(g, Vec3(0, 0, 1), 256);
  std::set<int32_t> seen(view.items.begin(), view.items.end());
  EXPECT_EQ(seen, (std::set<int32_t>{-1, 3, 7, 11, 1000}));
  const float pixel = view.window_side_m / 256.0f;
  for (int k = 0; k < 4; ++k) {
    const int px = static_cast<int>((1.5f * k - view.window_origin.x) / pixel);
    const int py = static_cast<int>((view.window_origin.y + view.window_side_m - 0.7f * k) / pixel);
    EXPECT_EQ(view.items[static_cast<size_t>(py * 256 + px)], ids[k]);
  }
}

TEST(LightView, CoverageInvariantUnderRotationAboutTheLightAxis) {
  const Vec3 light = glm::normalize(Vec3(0.3f, -0.2f, 1.0f));
  LightViewGeometry g;
  Pcg32 rng(9);
  for (int k = 0; k < 40; ++k) {
    const Vec3 c(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(0, 3));
    const Vec3 n(rng.symmetric(), rng.symmetric(), 1.0f + rng.uniform());
    add_square(g, c, n, rng.uniform(0.3f, 0.8f), rng.uniform(0, kPi), k % 10);
  }
  add_square(g, Vec3(0, 0, 1.5f), Vec3(0, 0, 1), 1.0f, 0.0f, -1);
  const std::vector<float> base = intercepted_area(render_light_view(g, light, 768), 10);
  for (const float angle_deg : {17.0f, 63.0f, 140.0f}) {
    const Mat4 rot = glm::rotate(Mat4(1.0f), radians(angle_deg), light);
    LightViewGeometry r = g;
    for (Vec3& v : r.vertices) v = Vec3(rot * Vec4(v, 1.0f));
    const std::vector<float> area = intercepted_area(render_light_view(r, light, 768), 10);
    float total = 0.0f, total_base = 0.0f;
    for (int i = 0; i < 10; ++i) {
      EXPECT_NEAR(area[static_cast<size_t>(i)], base[static_cast<size_t>(i)],
                  0.02f * base[static_cast<size_t>(i)] + 1e-3f)
          << "item " << i << " turned " << angle_deg;
      total += area[static_cast<size_t>(i)];
      total_base += base[static_cast<size_t>(i)];
    }
    EXPECT_NEAR(total, total_base, 0.005f * total_base);
  }
}

TEST(LightView, SunAtEquinoxNoonStandsAtNinetyMinusLatitude) {
  // Day 81: Cooper's declination is 0.
  const Vec3 sun = sun_direction(radians(40.0f), 81, 0.0f);
  EXPECT_NEAR(std::asin(sun.z), radians(50.0f), 1e-4f);
  EXPECT_LT(sun.y, 0.0f);  // due south in the northern hemisphere
  EXPECT_NEAR(sun.x, 0.0f, 1e-5f);
  const Vec3 afternoon = sun_direction(radians(40.0f), 81, 0.5f);
  EXPECT_LT(afternoon.x, 0.0f);  // the sun moves west
}

TEST(LightView, SkyDirectionsAreCosineWeighted) {
  // E[cos θ] = 2/3 for a cosine-weighted hemisphere, variance 1/2 − 4/9.
  LightDirections d;
  d.sun_weight = 0.0f;
  const int n = 40000;
  double sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const Vec3 w = sample_light_direction(d, hash_ids(1, k));
    ASSERT_GT(w.z, 0.0f);
    sum += w.z;
  }
  const double sigma = std::sqrt((0.5 - 4.0 / 9.0) / n);
  EXPECT_NEAR(sum / n, 2.0 / 3.0, 4.5 * sigma);
}

TEST(LightView, SunDirectionsFollowTheSeason) {
  LightDirections d;
  d.sun_weight = 1.0f;
  d.latitude_deg = 50.0f;
  d.first_day = d.last_day = 172;  // midsummer: the sun never climbs above 90 − 50 + 23.45
  const float max_elevation = radians(90.0f - 50.0f + 23.45f);
  int south = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 w = sample_light_direction(d, hash_ids(2, k));
    ASSERT_GT(w.z, 0.0f);
    EXPECT_LE(std::asin(w.z), max_elevation + 1e-3f);
    south += w.y < 0.0f ? 1 : 0;
  }
  EXPECT_GT(south, 1200);  // mostly from the south at 50° N
}

}  // namespace
}  // namespace sylva
