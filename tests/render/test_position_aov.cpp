// The position AOV (P.X/P.Y/P.Z): world position of the surface through each pixel centre.

#include "geometry/primitives.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

namespace sylva {
namespace {

TEST(PositionAov, LiesOnTheHitSurfaceAndAlongTheCameraRay) {
  // Ground z = 0 (instance 0) and a 1 m box centred at (0.5, 1, 0.5) (instance 1; make_box puts
  // its base on z = 0), seen obliquely.
  Scene s;
  s.camera.position = {3, -4, 2.5f};
  s.camera.target = {0, 1, 0.3f};
  const uint32_t m = s.add_material("grey", make_diffuse("grey", DenseSpectrum::constant(0.5f)));
  s.instances.push_back(
      {s.add_prototype(Prototype{"ground", make_plane(20, 20), m, {}, 0, {}, {}, {}, 0, {}, 0}), Mat4(1.0f), 0});
  s.instances.push_back({s.add_prototype(Prototype{"box", make_box(Vec3(1.0f)), m, {}, 0, {}, {}, {}, 0, {}, 0}),
                         glm::translate(Mat4(1.0f), Vec3(0.5f, 1, 0.0f)), 0});
  Renderer r(s, test::test_settings(48, 32, 1, 4));
  Film film = r.make_film();
  r.render(film);
  const Image img = r.make_image(film);
  const int px = img.find_channel("P.X"), py = img.find_channel("P.Y"), pz = img.find_channel("P.Z"),
            z = img.find_channel("Z"), id = img.find_channel("id.instance");
  ASSERT_GE(px, 0);
  ASSERT_GE(py, 0);
  ASSERT_GE(pz, 0);
  const Vec3 forward = glm::normalize(s.camera.target - s.camera.position);
  int ground = 0, box = 0, sky = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Vec3 p(img.at(x, y, px), img.at(x, y, py), img.at(x, y, pz));
      const int inst = static_cast<int>(img.at(x, y, id));
      if (inst == 0) {
        ++sky;
        EXPECT_GT(glm::length(p - s.camera.position), 1e9f);
        continue;
      }
      // Camera-space depth is the offset from the camera along the view axis.
      EXPECT_NEAR(glm::dot(p - s.camera.position, forward), img.at(x, y, z), 1e-4f * img.at(x, y, z));
      if (inst == 1) {
        ++ground;
        EXPECT_NEAR(p.z, 0.0f, 1e-4f);
        EXPECT_LE(std::abs(p.x), 10.0f + 1e-3f);
      } else {
        ++box;
        // On the box's surface: inside its bounds, on one of its faces.
        const Vec3 d = glm::abs(p - Vec3(0.5f, 1, 0.5f));
        EXPECT_LE(std::max({d.x, d.y, d.z}), 0.5f + 1e-4f);
        EXPECT_NEAR(std::max({d.x, d.y, d.z}), 0.5f, 1e-4f);
      }
    }
  EXPECT_GT(ground, 50);
  EXPECT_GT(box, 20);
  EXPECT_GT(sky, 20);
}

}  // namespace
}  // namespace sylva
