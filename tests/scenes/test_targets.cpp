// [[targets]] (snapping, labels), the label AOVs id.class / id.variant, and the JSON sidecar:
// a target's id.object covers exactly the pixels whose first hit is the target (checked against an
// independent brute-force ray cast), the sidecar's boxes and counts agree with the AOV.

#include "core/error.h"
#include "render/coverage.h"
#include "render/renderer.h"
#include "render/sensors/camera.h"
#include "scenes/scene_file.h"
#include "scenes/sections/scene_builder.h"
#include "scenes/sidecar.h"
#include "tests/support/json_parse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <string>

namespace sylva {
namespace {

const std::string kMaterials = R"(
[camera]
position = [0.0, -16.0, 4.0]
target = [0.0, 0.0, 1.0]
[sun]
elevation = 50
[materials.grey]
reflectance = 0.3
[materials.camo]
reflectance = { file = "spectra/target_paints.csv", column = "camouflage_green" }
[[meshes]]
name = "ground"
shape = "plane"
size = [200, 200]
material = "grey"
)";

SceneFile parse(const std::string& text) {
  return parse_scene(text, "targets.toml", SYLVA_SOURCE_DIR "/data/examples");
}

std::string target_error(const std::string& text) {
  try {
    parse(text);
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

Image render_labels(const SceneFile& f, int w, int h) {
  RenderSettings s = render_settings(f);
  s.width = w;
  s.height = h;
  s.spp = 1;
  s.progress = false;
  Renderer r(f.scene, s);
  Film film = r.make_film();
  r.render(film);
  return r.make_image(film);
}

// The index of the instance a ray meets first, by brute force over every triangle in world space
// (double precision Möller–Trumbore), independent of Embree; nullopt for the sky.
std::optional<uint32_t> first_hit_brute_force(const Scene& scene, const Ray& ray) {
  double best = INFINITY;
  std::optional<uint32_t> out;
  const glm::dvec3 o(ray.origin), d(ray.direction);
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const TriangleMesh& m = scene.prototypes[inst.prototype].triangles;
    const glm::dmat4 w(inst.world_from_object);
    for (const glm::uvec3& t : m.triangles) {
      const glm::dvec3 a(w * glm::dvec4(glm::dvec3(m.positions[t.x]), 1.0));
      const glm::dvec3 b(w * glm::dvec4(glm::dvec3(m.positions[t.y]), 1.0));
      const glm::dvec3 c(w * glm::dvec4(glm::dvec3(m.positions[t.z]), 1.0));
      const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
      const double det = glm::dot(e1, p);
      if (det == 0) continue;
      const glm::dvec3 s = o - a, q = glm::cross(s, e1);
      const double u = glm::dot(s, p) / det, v = glm::dot(d, q) / det, tt = glm::dot(e2, q) / det;
      if (u < 0 || v < 0 || u + v > 1 || tt <= 0 || tt >= best) continue;
      best = tt;
      out = i;
    }
  }
  return out;
}

TEST(Targets, SnapToTheHighestGroundUnderTheFootprint) {
  // A 0.5 m pad under the first target, nothing special under the second, the third not snapped.
  const SceneFile f = parse(kMaterials + R"(
[[meshes]]
name = "pad"
shape = "box"
size = [8, 10, 0.5]
material = "grey"
[[targets]]
file = "targets/vehicle.obj"
material = "camo"
label = "vehicle"
position = [0, 0, 7]
heading = 30
[[targets]]
name = "far"
file = "targets/vehicle.obj"
material = "camo"
label = "vehicle"
position = [30, 30, 7]
[[targets]]
file = "targets/vehicle.obj"
material = "camo"
label = "crate"
position = [-30, 0, 2]
ground = "none"
)");
  ASSERT_EQ(f.targets.size(), 3u);
  const auto lowest_z = [&](const TargetInfo& t) {
    const Instance& inst = f.scene.instances[t.instance];
    float lo = INFINITY;
    for (const Vec3& p : f.scene.prototypes[inst.prototype].triangles.positions)
      lo = std::min(lo, Vec3(inst.world_from_object * Vec4(p, 1.0f)).z);
    return lo;
  };
  EXPECT_NEAR(lowest_z(f.targets[0]), 0.5f, 1e-5f);
  EXPECT_NEAR(lowest_z(f.targets[1]), 0.0f, 1e-5f);
  EXPECT_NEAR(lowest_z(f.targets[2]), 2.0f, 1e-5f);
  EXPECT_EQ(f.targets[0].name, "target1");
  EXPECT_EQ(f.targets[1].name, "far");
  // Heading is a compass bearing: the mesh's +Y (forward) points 30° east of north.
  const Mat4& m = f.scene.instances[f.targets[0].instance].world_from_object;
  const Vec3 forward = glm::normalize(Vec3(m * Vec4(0, 1, 0, 0)));
  EXPECT_NEAR(forward.x, std::sin(radians(30.0f)), 1e-6f);
  EXPECT_NEAR(forward.y, std::cos(radians(30.0f)), 1e-6f);
  // Labels: one class per label, its id from its name; distinct object ids; one variant (same mesh
  // and material) shared by all three.
  EXPECT_EQ(f.scene.class_names.at(f.targets[0].class_id), "vehicle");
  EXPECT_EQ(f.scene.class_names.at(f.targets[2].class_id), "crate");
  EXPECT_EQ(f.targets[0].class_id, class_id_of("vehicle"));
  EXPECT_EQ(f.targets[0].class_id, f.targets[1].class_id);
  EXPECT_NE(f.targets[0].object_id, f.targets[1].object_id);
  EXPECT_NE(f.targets[1].object_id, f.targets[2].object_id);
  EXPECT_GT(f.targets[0].object_id, 0u);
  EXPECT_EQ(f.targets[0].variant_id, f.targets[2].variant_id);
  EXPECT_EQ(f.variants.at(f.targets[0].variant_id - 1).kind, "target");
}

TEST(Targets, BadEntriesAreFileLineErrors) {
  const std::string target = "[[targets]]\nfile = \"targets/vehicle.obj\"\nmaterial = \"camo\"\n";
  EXPECT_NE(target_error(kMaterials + target + "position = [0, 0, 0]\n").find("label"), std::string::npos);
  EXPECT_NE(target_error(kMaterials + target + "label = \"v\"\n").find("position"), std::string::npos);
  EXPECT_NE(
      target_error(kMaterials + target + "label = \"v\"\nposition = [0,0,0]\nground = \"up\"\n").find("targets.toml:"),
      std::string::npos);
  // Nothing to snap onto (outside the 200 m ground).
  EXPECT_NE(target_error(kMaterials + target + "label = \"v\"\nposition = [500, 0, 0]\n").find("nothing to snap to"),
            std::string::npos);
  EXPECT_NE(target_error(kMaterials + target + "label = \"v\"\nposition = [0, 0, 0]\ncolour = 1\n").find("colour"),
            std::string::npos);
}

// A target half behind a wall: id.object covers exactly the pixels whose first hit is the target.
const std::string kOccluded = kMaterials + R"(
[[meshes]]
name = "wall"
shape = "box"
size = [3, 0.3, 2.5]
translate = [-1.5, -6, 0]
material = "grey"
object_id = 5
[[targets]]
name = "tank"
file = "targets/vehicle.obj"
material = "camo"
label = "vehicle"
position = [0, 0, 0]
heading = 90
)";

TEST(Targets, ObjectAovCoversExactlyThePixelsWhoseFirstHitIsTheTarget) {
  const SceneFile f = parse(kOccluded);
  ASSERT_EQ(f.targets.size(), 1u);
  EXPECT_EQ(f.targets[0].object_id, 6u) << "automatic ids follow the largest explicit one";
  const int w = 96, h = 64;
  const Image img = render_labels(f, w, h);
  const int id = img.find_channel("id.object");
  ASSERT_GE(id, 0);
  const Camera camera(f.scene.camera, w, h);
  int target_pixels = 0, wall_pixels = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::optional<uint32_t> first =
          first_hit_brute_force(f.scene, camera.generate_ray(Vec2(x + 0.5f, y + 0.5f), Vec2(0.5f)));
      const bool is_target = first && *first == f.targets[0].instance;
      EXPECT_EQ(static_cast<uint32_t>(img.at(x, y, id)) == f.targets[0].object_id, is_target) << x << "," << y;
      target_pixels += is_target;
      wall_pixels += static_cast<uint32_t>(img.at(x, y, id)) == 5u;
    }
  EXPECT_GT(target_pixels, 100);
  EXPECT_GT(wall_pixels, 50);
}

TEST(Targets, SidecarBoxesAndCountsMatchTheAov) {
  const SceneFile f = parse(kOccluded);
  const int w = 96, h = 64;
  const Image img = render_labels(f, w, h);
  RenderSettings settings = render_settings(f);
  settings.width = w;
  settings.height = h;
  const test::Json j = test::parse_json(make_sidecar(f, settings, img, "out.exr"));
  EXPECT_EQ(j["format"].string, "sylva-labels");
  EXPECT_EQ(j["image"]["width"].number, w);
  EXPECT_EQ(j["classes"][0]["name"].string, "sky");
  const test::Json& t = j["targets"][0];
  EXPECT_EQ(t["name"].string, "tank");
  EXPECT_EQ(t["label"].string, "vehicle");
  const uint32_t object = static_cast<uint32_t>(t["object"].number);
  const int id = img.find_channel("id.object");
  int visible = 0, x0 = w, y0 = h, x1 = -1, y1 = -1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (static_cast<uint32_t>(img.at(x, y, id)) == object) {
        ++visible;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        // Every visible pixel lies inside the box.
        EXPECT_GE(x, t["image_box"]["x0"].number);
        EXPECT_LE(x, t["image_box"]["x1"].number);
        EXPECT_GE(y, t["image_box"]["y0"].number);
        EXPECT_LE(y, t["image_box"]["y1"].number);
      }
  EXPECT_EQ(t["visible_pixels"].number, visible);
  // The box is the tight one.
  EXPECT_EQ(t["image_box"]["x0"].number, x0);
  EXPECT_EQ(t["image_box"]["y1"].number, y1);
  // The wall hides part of it: fewer visible than unoccluded pixels, and the fraction says so.
  const double alone = t["unoccluded_pixels"].number;
  EXPECT_GT(alone, visible);
  EXPECT_NEAR(t["visible_fraction"].number, visible / alone, 1e-12);
  EXPECT_NEAR(t["occluded_fraction"].number, 1 - visible / alone, 1e-12);
  // The object table holds the wall (visible) and the target, with world bounds around the target.
  bool wall = false;
  for (const test::Json& o : j["objects"].array) {
    if (o["id"].number == 5) wall = true;
    if (o["id"].number == object) {
      EXPECT_EQ(o["class_name"].string, "vehicle");
      EXPECT_NEAR(o["bounds"]["min"][2].number, 0.0, 1e-5);
      EXPECT_NEAR(o["bounds"]["max"][2].number, 2.3, 1e-5);
    }
  }
  EXPECT_TRUE(wall);
}

TEST(Targets, UnoccludedCountEqualsVisibleWithoutOccluders) {
  const SceneFile f = parse(kMaterials + R"(
[[targets]]
file = "targets/vehicle.obj"
material = "camo"
label = "vehicle"
position = [0, 0, 0]
)");
  const Image img = render_labels(f, 64, 48);
  uint64_t visible = 0;
  const int id = img.find_channel("id.object");
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) visible += static_cast<uint32_t>(img.at(x, y, id)) == f.targets[0].object_id;
  EXPECT_GT(visible, 50u);
  EXPECT_EQ(unoccluded_pixels(f.scene, {f.targets[0].instance}, 64, 48, 0), std::vector<uint64_t>{visible});
}

TEST(LabelAovs, ClassAndVariantOfTreesTargetsGroundAndSky) {
  const SceneFile f = parse(kMaterials + R"(
[materials.leaf]
type = "leaf"
reflectance = 0.4
transmittance = 0.3
[[trees]]
species = "../species/quaking_aspen.toml"
seed = 3
quality = 0.3
bark = "grey"
leaf = "leaf"
translate = [-4, 2, 0]
[[trees]]
species = "../species/black_tupelo.toml"
seed = 1
quality = 0.3
bark = "grey"
leaf = "leaf"
translate = [4, 2, 0]
[[targets]]
file = "targets/vehicle.obj"
material = "camo"
label = "vehicle"
position = [0, -3, 0]
)");
  // Class table: the built-in classes, then the two species and the label, each id from its name.
  ASSERT_EQ(f.scene.class_names.size(), 4u + 3u);
  const uint32_t aspen = class_id_of(f.variants[0].name), tupelo = class_id_of(f.variants[1].name),
                 vehicle = class_id_of("vehicle");
  EXPECT_EQ(f.scene.class_names.at(vehicle), "vehicle");
  ASSERT_EQ(f.variants.size(), 3u);
  EXPECT_EQ(f.variants[0].seed, 3u);
  EXPECT_EQ(f.variants[0].class_id, aspen);
  EXPECT_EQ(f.variants[1].class_id, tupelo);
  const Image img = render_labels(f, 96, 64);
  const int cls = img.find_channel("id.class"), var = img.find_channel("id.variant"),
            inst = img.find_channel("id.instance");
  ASSERT_GE(cls, 0);
  ASSERT_GE(var, 0);
  std::map<uint32_t, int> seen;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const auto c = static_cast<uint32_t>(img.at(x, y, cls));
      const auto v = static_cast<uint32_t>(img.at(x, y, var));
      const auto i = static_cast<uint32_t>(img.at(x, y, inst));
      ASSERT_EQ(f.scene.class_names.count(c), 1u) << c;
      ++seen[c];
      if (i == 0) {
        EXPECT_EQ(c, kClassSky);
        EXPECT_EQ(v, 0u);
        continue;
      }
      const Instance& hit = f.scene.instances[i - 1];
      EXPECT_EQ(c, hit.class_id);
      EXPECT_EQ(v, hit.variant_id);
      const uint32_t expected = c == aspen ? 1u : c == tupelo ? 2u : c == vehicle ? 3u : 0u;
      EXPECT_EQ(v, expected) << "class " << c;
    }
  EXPECT_GT(seen[kClassSky], 0);
  EXPECT_GT(seen[kClassMesh], 0);
  EXPECT_GT(seen[aspen], 0);
  EXPECT_GT(seen[tupelo], 0);
  EXPECT_GT(seen[vehicle], 0);
}

}  // namespace
}  // namespace sylva
