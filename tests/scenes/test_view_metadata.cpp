// Camera and sun metadata (scenes/view_metadata.h) in the EXR header and the label sidecar: read
// back and checked against the scene — a world point projected with K and world_from_camera lands
// on the pixel whose id AOV names the object there, and the camera's own ray through that raster
// position passes through the point.

#include "core/image.h"
#include "render/renderer.h"
#include "render/sensors/camera.h"
#include "scenes/scene_file.h"
#include "scenes/sidecar.h"
#include "scenes/view_metadata.h"
#include "tests/support/json_parse.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace sylva {
namespace {

// Three small spheres, each its own object, seen by the camera `camera` (TOML lines).
std::string scene_text(const std::string& camera) {
  return R"([render]
width = 64
height = 48
spp = 1
bands = ["rgb"]
max_depth = 1
[camera]
)" + camera +
         R"(
[sun]
azimuth = 120
elevation = 30
[materials.grey]
reflectance = 0.4
[[meshes]]
shape = "sphere"
radius = 0.35
material = "grey"
object_id = 7
translate = [0.0, 0.0, 1.0]
[[meshes]]
shape = "sphere"
radius = 0.35
material = "grey"
object_id = 8
translate = [-2.0, 1.5, 2.0]
[[meshes]]
shape = "sphere"
radius = 0.35
material = "grey"
object_id = 9
translate = [1.8, -1.0, 0.2]
)";
}

struct Known {
  glm::dvec3 centre;
  float object;
};
const Known kSpheres[] = {{{0.0, 0.0, 1.0}, 7}, {{-2.0, 1.5, 2.0}, 8}, {{1.8, -1.0, 0.2}, 9}};

Image render_labels(const SceneFile& f) {
  RenderSettings s = render_settings(f);
  s.progress = false;
  Renderer r(f.scene, s);
  Film film = r.make_film();
  r.render(film);
  Image image = r.make_image(film);
  annotate_render(image, f, s);
  return image;
}

std::vector<double> numbers_of(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> out;
  for (double v = 0; in >> v;) out.push_back(v);
  return out;
}

// K and world_from_camera as the header holds them (row-major).
CameraMetadata camera_from_header(const Image& image) {
  CameraMetadata c;
  c.projection = image.attribute("sylva:camera_projection");
  c.width = image.width;
  c.height = image.height;
  const std::vector<double> k = numbers_of(image.attribute("sylva:camera_intrinsics"));
  const std::vector<double> m = numbers_of(image.attribute("sylva:world_from_camera"));
  EXPECT_EQ(k.size(), 9u);
  EXPECT_EQ(m.size(), 16u);
  if (k.size() != 9 || m.size() != 16) return c;
  c.fx = k[0];
  c.cx = k[2];
  c.fy = k[4];
  c.cy = k[5];
  EXPECT_EQ(k[1], 0.0);
  EXPECT_EQ(k[3], 0.0);
  EXPECT_EQ(k[8], 1.0);
  for (int r = 0; r < 4; ++r)
    for (int col = 0; col < 4; ++col) c.world_from_camera[col][r] = m[static_cast<size_t>(r * 4 + col)];
  return c;
}

class ViewMetadata : public test::TempDirTest {};

void expect_spheres_where_projected(const SceneFile& f) {
  const Image rendered = render_labels(f);
  const std::filesystem::path exr =
      std::filesystem::temp_directory_path() / ("sylva_view_metadata_" + std::to_string(::getpid()) + ".exr");
  write_exr(exr, rendered);
  const Image image = read_exr(exr);
  std::filesystem::remove(exr);
  const CameraMetadata camera = camera_from_header(image);
  const int object = image.find_channel("id.object");
  ASSERT_GE(object, 0);
  const Camera cam(f.scene.camera, image.width, image.height);
  for (const Known& k : kSpheres) {
    const std::optional<glm::dvec2> uv = project_to_raster(camera, k.centre);
    ASSERT_TRUE(uv.has_value());
    const int x = static_cast<int>(std::floor(uv->x)), y = static_cast<int>(std::floor(uv->y));
    ASSERT_TRUE(x >= 0 && x < image.width && y >= 0 && y < image.height) << uv->x << " " << uv->y;
    EXPECT_EQ(image.at(x, y, object), k.object) << "sphere " << k.object << " at pixel " << x << ", " << y;
    // The camera's own ray through (u, v) passes through the centre (to float precision).
    const Ray ray = cam.generate_ray(Vec2(static_cast<float>(uv->x), static_cast<float>(uv->y)), Vec2(0.5f));
    const glm::dvec3 o(ray.origin), d(ray.direction);
    const double along = glm::dot(k.centre - o, d);
    EXPECT_LT(glm::length(k.centre - (o + along * d)), 1e-4) << "sphere " << k.object;
  }
}

TEST_F(ViewMetadata, PerspectiveProjectsKnownPointsOntoTheirIds) {
  const SceneFile f =
      parse_scene(scene_text("position = [3.0, -9.0, 3.5]\ntarget = [0.0, 0.0, 1.0]\nvfov = 40"), "view.toml", dir_);
  expect_spheres_where_projected(f);
  const CameraMetadata c = camera_metadata(f.scene.camera, 64, 48);
  EXPECT_NEAR(c.fx, 24.0 / std::tan(glm::radians(20.0)), 1e-9);
  EXPECT_EQ(c.cx, 32.0);
  EXPECT_EQ(c.cy, 24.0);
}

TEST_F(ViewMetadata, OrthographicProjectsKnownPointsOntoTheirIds) {
  const SceneFile f = parse_scene(
      scene_text("type = \"orthographic\"\nwidth = 8.0\nposition = [0.5, -0.5, 30.0]\ntarget = [0.5, -0.4, 0.0]"),
      "view.toml", dir_);
  expect_spheres_where_projected(f);
  const Image image = render_labels(f);
  EXPECT_EQ(image.attribute("sylva:camera_projection"), "orthographic");
  EXPECT_EQ(numbers_of(image.attribute("sylva:camera_metres_per_pixel")), std::vector<double>{8.0 / 64});
}

TEST_F(ViewMetadata, SunAndBandsInHeaderAndSidecar) {
  const SceneFile f =
      parse_scene(scene_text("position = [3.0, -9.0, 3.5]\ntarget = [0.0, 0.0, 1.0]\nvfov = 40"), "view.toml", dir_);
  const Image image = render_labels(f);
  const std::vector<double> sun = numbers_of(image.attribute("sylva:sun_direction"));
  ASSERT_EQ(sun.size(), 3u);
  // Azimuth 120° (east-south-east), elevation 30°: +X east, +Y north, +Z up.
  EXPECT_NEAR(sun[0], std::sin(glm::radians(120.0)) * std::cos(glm::radians(30.0)), 1e-12);
  EXPECT_NEAR(sun[1], std::cos(glm::radians(120.0)) * std::cos(glm::radians(30.0)), 1e-12);
  EXPECT_NEAR(sun[2], 0.5, 1e-12);
  EXPECT_EQ(image.attribute("sylva:sun_elevation_deg"), "30");
  EXPECT_EQ(image.attribute("sylva:bands"), "rgb");

  RenderSettings s = render_settings(f);
  const test::Json j = test::JsonParser(make_sidecar(f, s, image, dir_ / "view.exr")).parse();
  EXPECT_EQ(j["camera"]["projection"].string, "perspective");
  const CameraMetadata header = camera_from_header(image);
  EXPECT_EQ(j["camera"]["intrinsics"][0].number, header.fx);
  EXPECT_EQ(j["camera"]["intrinsics"][2].number, header.cx);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_EQ(j["camera"]["world_from_camera"][static_cast<size_t>(r * 4 + c)].number,
                header.world_from_camera[c][r]);
  EXPECT_NEAR(j["sun"]["direction"][2].number, 0.5, 1e-12);
  EXPECT_EQ(j["sun"]["azimuth_deg"].number, 120.0);
  ASSERT_EQ(j["bands"].array.size(), 1u);
  EXPECT_EQ(j["bands"][0].string, "rgb");
}

}  // namespace
}  // namespace sylva
