// The label sidecar's object boxes for every primitive kind (render/primitives/primitive.h's
// prototype_bounds): a labelled [[canopies]] layer of exact discs and a grass patch of ribbons get
// boxes that hold every point of their geometry and are tight to it; the scene's bounds
// (EmbreeScene::bounds) are the same boxes, and the OBJ exporter's flattened mesh lies in them.

#include "core/image.h"
#include "geometry/grass.h"
#include "render/embree_scene.h"
#include "render/flatten.h"
#include "render/primitives/primitive.h"
#include "scenes/scene_file.h"
#include "scenes/sidecar.h"
#include "tests/support/json_parse.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace sylva {
namespace {

const std::string kCanopy = R"(
[materials.leaf]
type = "leaf"
reflectance = 0.4
transmittance = 0.3
[[canopies]]
type = "homogeneous"
lai = 1
height = 1.5
size = [2, 2]
disc_radius = 0.1
leaf_angles = "uniform"
material = "leaf"
object_id = 7
translate = [3, -2, 0.5]
)";

// The sidecar entry of object `id`.
const test::Json& object_entry(const test::Json& j, uint32_t id) {
  for (const test::Json& o : j["objects"].array)
    if (static_cast<uint32_t>(o["id"].number) == id) return o;
  throw std::runtime_error("no sidecar object " + std::to_string(id));
}

// Checks that `box` (a sidecar bounds) holds every point of `points` and lies within `slack` of
// their own box on every side.
void expect_box_of(const test::Json& box, const Bounds3& truth, double slack, const char* what) {
  ASSERT_FALSE(box.is_null()) << what << ": no bounds";
  for (int a = 0; a < 3; ++a) {
    const double lo = box["min"][a].number, hi = box["max"][a].number;
    EXPECT_LE(lo, truth.lo[a] + 1e-6) << what << " axis " << a;
    EXPECT_GE(hi, truth.hi[a] - 1e-6) << what << " axis " << a;
    EXPECT_GE(lo, truth.lo[a] - slack) << what << " axis " << a;
    EXPECT_LE(hi, truth.hi[a] + slack) << what << " axis " << a;
  }
}

// The canopy (object 7) and a grass patch, moved and turned a quarter turn (which turns its box into
// the box of the turned patch), as its own object (8).
SceneFile canopy_and_grass() {
  SceneFile f = parse_scene(kCanopy, "c.toml", SYLVA_SOURCE_DIR "/data/examples");
  Prototype grass;
  grass.name = "grass";
  grass.curves = make_grass_patch(GrassParams{}, 5);
  const uint32_t grass_proto = f.scene.add_prototype(std::move(grass));
  Instance placed{grass_proto};
  placed.world_from_object =
      glm::translate(Mat4(1.0f), Vec3(-4, 1, 0.2f)) * glm::rotate(Mat4(1.0f), 0.5f * kPi, Vec3(0, 0, 1));
  placed.object_id = 8;
  placed.class_id = kClassGrass;
  f.scene.instances.push_back(placed);
  return f;
}

// The sidecar of `f` over a 4×2 image that shows objects 7 and 8.
test::Json sidecar_of(const SceneFile& f) {
  Image image = make_image(4, 2, {"id.object", "id.class"});
  image.at(0, 0, 0) = 7;
  image.at(1, 0, 0) = 8;
  RenderSettings settings;
  settings.width = image.width;
  settings.height = image.height;
  return test::parse_json(make_sidecar(f, settings, image, "out.exr"));
}

Bounds3 box_of(const test::Json& box) {
  Bounds3 b;
  b.extend(Vec3(box["min"][0].number, box["min"][1].number, box["min"][2].number));
  b.extend(Vec3(box["max"][0].number, box["max"][1].number, box["max"][2].number));
  return b;
}

TEST(Sidecar, DiscCanopyAndGrassPatchGetTheBoxesOfTheirGeometry) {
  SceneFile f = canopy_and_grass();
  const Scene& scene = f.scene;

  // What each object's geometry covers in the world: the discs' rims, the ribbons finely tessellated.
  Bounds3 canopy, blades;
  for (const Instance& inst : scene.instances) {
    const Prototype& p = scene.prototypes[inst.prototype];
    const auto world = [&](const Vec3& v) { return Vec3(inst.world_from_object * Vec4(v, 1.0f)); };
    if (inst.object_id == 7)
      for (size_t i = 0; i < p.discs.size(); ++i) {
        const Frame frame = Frame::from_z(glm::normalize(p.discs.normal[i]));
        for (int k = 0; k < 720; ++k) {
          const float a = kTwoPi * static_cast<float>(k) / 720.0f;
          canopy.extend(world(p.discs.centre[i] + p.discs.radius[i] * (std::cos(a) * frame.x + std::sin(a) * frame.y)));
        }
      }
    if (inst.object_id == 8) {
      std::vector<Vec3> points;
      std::vector<glm::uvec4> quads;
      tessellate_ribbons(p.curves, 64, points, quads);
      for (const Vec3& v : points) blades.extend(world(v));
    }
  }
  ASSERT_FALSE(canopy.empty());
  ASSERT_FALSE(blades.empty());

  const test::Json j = sidecar_of(f);
  // Discs: exact boxes, to the rim sampling's 1 − cos(π/720) of a radius.
  expect_box_of(object_entry(j, 7)["bounds"], canopy, 1e-3, "canopy");
  // Ribbons: their control polygons grown by a blade's half-width; a bent blade's polygon reaches a
  // little beyond the blade itself.
  expect_box_of(object_entry(j, 8)["bounds"], blades, 0.05, "grass");
}

TEST(Sidecar, SceneSidecarAndObjExportShareOneBounds) {
  SceneFile f = canopy_and_grass();
  const test::Json j = sidecar_of(f);
  const Bounds3 canopy = box_of(object_entry(j, 7)["bounds"]), grass = box_of(object_entry(j, 8)["bounds"]);
  // The scene's bounds: the union of the sidecar's boxes, padded by a few ulps.
  const EmbreeScene embree(f.scene);
  const Bounds3 both = merged(canopy, grass);
  for (int a = 0; a < 3; ++a) {
    const float ulps = 1e-6f * (1.0f + std::abs(both.lo[a]) + std::abs(both.hi[a]));
    EXPECT_LE(embree.bounds().lo[a], both.lo[a]) << "axis " << a;
    EXPECT_GE(embree.bounds().lo[a], both.lo[a] - ulps) << "axis " << a;
    EXPECT_GE(embree.bounds().hi[a], both.hi[a]) << "axis " << a;
    EXPECT_LE(embree.bounds().hi[a], both.hi[a] + ulps) << "axis " << a;
  }
  // The OBJ exporter's mesh (the discs as inscribed 12-gons; grass is not exported) lies in the
  // canopy's box and reaches each of its sides to within the polygon's 1 − cos(π/12) of a radius.
  const FlatScene flat = flatten_scene(f.scene);
  ASSERT_FALSE(flat.mesh.positions.empty());
  Bounds3 exported;
  for (const Vec3& v : flat.mesh.positions) exported.extend(v);
  expect_box_of(object_entry(j, 7)["bounds"], exported, 0.1 * (1.0 - std::cos(kPi / 12.0)) + 1e-5, "exported canopy");
}

}  // namespace
}  // namespace sylva
