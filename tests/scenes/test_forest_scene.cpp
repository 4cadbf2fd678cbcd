// Forest scenes (docs/scene_format.md [terrain], [[grass]], [vegetation]): terrain rasters read at
// their pixel centres, trees from a feature map with their own object ids on the ground, and a
// clear `file:line: message` naming the raster for every bad input.

#include "core/error.h"
#include "geometry/terrain.h"
#include "scenes/scene_file.h"
#include "tests/support/temp_dir.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <set>

namespace sylva {
namespace {

template <typename T>
void write_raster(const std::filesystem::path& file, int w, int h, int channels, OIIO::TypeDesc type,
                  const std::vector<T>& values) {
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(w, h, channels, type)));
  ASSERT_TRUE(out->write_image(type, values.data()));
  ASSERT_TRUE(out->close());
}

const std::string kMaterials = R"(
[materials.soil]
reflectance = 0.2
[materials.bark]
reflectance = 0.3
[materials.leaf]
type = "leaf"
reflectance = 0.1
transmittance = 0.1
)";

class ForestScene : public test::TempDirTest {
 protected:
  SceneFile load(const std::string& text) {
    std::ofstream(dir_ / "scene.toml") << text;
    return load_scene_file(dir_ / "scene.toml");
  }
  // The message of the ParseError loading `text` throws; "" if it loads.
  std::string error_of(const std::string& text) {
    try {
      load(text);
    } catch (const ParseError& e) {
      return e.what();
    }
    return "";
  }
  std::string species() const { return std::string(SYLVA_SOURCE_DIR) + "/data/species/quaking_aspen.toml"; }
  // A terrain of w × h 16-bit pixels, 2 m each, heights 0.01 m per unit.
  void write_terrain(int w, int h) {
    std::vector<uint16_t> v;
    for (int i = 0; i < w * h; ++i) v.push_back(static_cast<uint16_t>(1000 + 37 * i));
    write_raster(dir_ / "terrain.png", w, h, 1, OIIO::TypeDesc::UINT16, v);
  }
  const std::string terrain_ = kMaterials + R"(
[terrain]
file = "terrain.png"
metres_per_pixel = 2
vertical_scale = 0.01
material = "soil"
)";
};

TEST_F(ForestScene, TerrainRasterHeightsAtPixelCentres) {
  const int w = 6, h = 4;
  std::vector<uint16_t> v;
  for (int i = 0; i < w * h; ++i) v.push_back(static_cast<uint16_t>(60000 - 2311 * i));
  write_raster(dir_ / "dem.png", w, h, 1, OIIO::TypeDesc::UINT16, v);
  const SceneFile f = load(kMaterials + R"(
[terrain]
file = "dem.png"
metres_per_pixel = 2
vertical_scale = 0.01
height_offset = 5
origin = [10, 20]
material = "soil"
object_id = 7
)");
  ASSERT_EQ(f.scene.prototypes.size(), 1u);
  const TriangleMesh& mesh = f.scene.prototypes[0].triangles;
  ASSERT_EQ(mesh.positions.size(), static_cast<size_t>(w * h));
  EXPECT_EQ(f.scene.instances[0].object_id, 7u);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Raster row y is node row h − 1 − y (rows run south); pixel centres 1 m inside the origin.
      const Vec3 p = mesh.positions[static_cast<size_t>((h - 1 - y) * w + x)];
      EXPECT_FLOAT_EQ(p.x, 11.0f + 2.0f * static_cast<float>(x));
      EXPECT_FLOAT_EQ(p.y, 21.0f + 2.0f * static_cast<float>(h - 1 - y));
      EXPECT_NEAR(p.z, 0.01f * static_cast<float>(v[static_cast<size_t>(y * w + x)]) + 5.0f, 1e-4f);
    }
  // A float raster reads its values as they are, `step` halves the resolution.
  std::vector<float> fv(static_cast<size_t>(9 * 5), 2.5f);
  write_raster(dir_ / "dem.exr", 9, 5, 1, OIIO::TypeDesc::FLOAT, fv);
  const SceneFile g = load(kMaterials + "[terrain]\nfile = \"dem.exr\"\nstep = 2\nmaterial = \"soil\"\n");
  EXPECT_EQ(g.scene.prototypes[0].triangles.positions.size(), 15u);
  EXPECT_FLOAT_EQ(g.scene.prototypes[0].triangles.positions[0].z, 2.5f);
  EXPECT_FLOAT_EQ(g.scene.prototypes[0].triangles.positions[0].x, -4.0f);  // centred: 18 m wide
}

TEST_F(ForestScene, CameraAboveTerrainStandsOnTheSurface) {
  write_terrain(10, 10);  // 20 m square, heights rising to the south-east
  const SceneFile f = load(terrain_ + "[camera]\nabove_terrain = true\nposition = [-3, 4, 1.7]\ntarget = [5, -2, 1]\n");
  const TriangleMesh& mesh = f.scene.prototypes[0].triangles;
  // The terrain mesh's own height under a point, by its triangles' planes (brute force).
  const auto ground = [&](Vec2 q) {
    for (const glm::uvec3& t : mesh.triangles) {
      const Vec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
      const float d = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
      const float u = ((q.x - a.x) * (c.y - a.y) - (c.x - a.x) * (q.y - a.y)) / d;
      const float v = ((b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y)) / d;
      if (u >= 0 && v >= 0 && u + v <= 1) return a.z + u * (b.z - a.z) + v * (c.z - a.z);
    }
    return std::numeric_limits<float>::quiet_NaN();
  };
  EXPECT_NEAR(f.scene.camera.position.z, ground(Vec2(-3, 4)) + 1.7f, 1e-4f);
  EXPECT_NEAR(f.scene.camera.target.z, ground(Vec2(5, -2)) + 1.0f, 1e-4f);
  EXPECT_NE(error_of(kMaterials + "[camera]\nabove_terrain = true\n").find("needs a [terrain]"), std::string::npos);
}

TEST_F(ForestScene, FeatureMapPlacesTreesWithTheirOwnIdsOnTheGround) {
  write_terrain(40, 40);  // 80 m square
  // Bit 0 on the west half, grass type 1 on the south half.
  std::vector<uint16_t> map;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) map.push_back(static_cast<uint16_t>((x < 10 ? 1u : 0u) | (y >= 10 ? 1u << 14 : 0u)));
  write_raster(dir_ / "features.png", 20, 20, 1, OIIO::TypeDesc::UINT16, map);
  const std::string text = terrain_ + R"(
[[grass]]
material = "leaf"
density = 50
patch_size = 4

[vegetation]
feature_map = "features.png"
seed = 2
[[vegetation.species]]
bit = 0
species = ")" + species() + R"("
bark = "bark"
leaf = "leaf"
quality = 0.2
density = 60
min_spacing = 4
variants = 2
scale = [0.5, 0.7]
)";
  const SceneFile f = load(text);
  // Prototypes: terrain, grass patch, then each variant's bark+leaves.
  ASSERT_EQ(f.scene.prototypes.size(), 4u);
  EXPECT_EQ(f.scene.prototypes[1].curves.size(), 800u);
  std::set<uint32_t> ids;
  size_t trees = 0, patches = 0;
  for (const Instance& inst : f.scene.instances) {
    const Vec3 at(inst.world_from_object[3]);
    if (inst.prototype >= 2) {
      ++trees;
      EXPECT_TRUE(ids.insert(inst.object_id).second) << "object id " << inst.object_id << " repeats";
      EXPECT_LT(at.x, 0.0f);  // the west half only
    } else if (inst.prototype == 1) {
      ++patches;
      EXPECT_LT(at.y, 0.0f);  // the south half only
      EXPECT_EQ(inst.object_id, 0u);
    }
  }
  // 0.32 ha of bit 0 at 60 trees/ha: about 19 trees.
  EXPECT_GT(trees, 5u);
  EXPECT_LT(trees, 40u);
  EXPECT_EQ(*ids.begin(), 1u);  // the first free id
  EXPECT_NEAR(static_cast<double>(patches), 200.0, 30.0);
  // The same file assembles the same scene.
  const SceneFile again = load(text);
  ASSERT_EQ(again.scene.instances.size(), f.scene.instances.size());
  for (size_t i = 0; i < f.scene.instances.size(); ++i)
    EXPECT_EQ(again.scene.instances[i].world_from_object, f.scene.instances[i].world_from_object);
  EXPECT_EQ(again.content_hash, f.content_hash);
  // Editing the feature map changes the scene hash (checkpoints and goldens see it).
  map[0] = 0;
  write_raster(dir_ / "features.png", 20, 20, 1, OIIO::TypeDesc::UINT16, map);
  EXPECT_NE(load(text).content_hash, f.content_hash);
}

TEST_F(ForestScene, BadRastersAndPlacementsNameTheirFile) {
  write_terrain(8, 8);
  const auto has = [this](const std::string& message, std::initializer_list<const char*> parts) {
    if (message.rfind((dir_ / "scene.toml:").string(), 0) != 0) return false;
    for (const char* p : parts)
      if (message.find(p) == std::string::npos) return false;
    return true;
  };
  std::string e = error_of(kMaterials + "[terrain]\nfile = \"missing.png\"\nmaterial = \"soil\"\n");
  EXPECT_TRUE(has(e, {"missing.png"})) << e;
  std::vector<uint8_t> bytes(64, 9);
  write_raster(dir_ / "eight.png", 8, 8, 1, OIIO::TypeDesc::UINT8, bytes);
  e = error_of(kMaterials + "[terrain]\nfile = \"eight.png\"\nmaterial = \"soil\"\n");
  EXPECT_TRUE(has(e, {"eight.png", "16-bit", "8-bit"})) << e;
  std::vector<uint16_t> rgb(3 * 64, 9);
  write_raster(dir_ / "rgb.png", 8, 8, 3, OIIO::TypeDesc::UINT16, rgb);
  e = error_of(kMaterials + "[terrain]\nfile = \"rgb.png\"\nmaterial = \"soil\"\n");
  EXPECT_TRUE(has(e, {"rgb.png", "one channel"})) << e;
  std::ofstream(dir_ / "garbage.png") << "not an image";
  e = error_of(kMaterials + "[terrain]\nfile = \"garbage.png\"\nmaterial = \"soil\"\n");
  EXPECT_TRUE(has(e, {"garbage.png"})) << e;

  const std::string species_entry = "[[vegetation.species]]\nbit = 0\nspecies = \"" + species() +
                                    "\"\nbark = \"bark\"\nleaf = \"leaf\"\nquality = 0.2\n";
  // Feature maps: 16-bit only, same aspect as the terrain, every set bit named, grass declared.
  write_raster(dir_ / "f8.png", 4, 4, 1, OIIO::TypeDesc::UINT8, std::vector<uint8_t>(16, 1));
  e = error_of(terrain_ + "[vegetation]\nfeature_map = \"f8.png\"\n" + species_entry);
  EXPECT_TRUE(has(e, {"f8.png", "16-bit"})) << e;
  write_raster(dir_ / "wide.png", 8, 4, 1, OIIO::TypeDesc::UINT16, std::vector<uint16_t>(32, 1));
  e = error_of(terrain_ + "[vegetation]\nfeature_map = \"wide.png\"\n" + species_entry);
  EXPECT_TRUE(has(e, {"wide.png", "aspect"})) << e;
  write_raster(dir_ / "bit3.png", 4, 4, 1, OIIO::TypeDesc::UINT16, std::vector<uint16_t>(16, 1 | 8));
  e = error_of(terrain_ + "[vegetation]\nfeature_map = \"bit3.png\"\n" + species_entry);
  EXPECT_TRUE(has(e, {"bit3.png", "bit 3"})) << e;
  write_raster(dir_ / "grass2.png", 4, 4, 1, OIIO::TypeDesc::UINT16, std::vector<uint16_t>(16, 2u << 14));
  e = error_of(terrain_ + "[vegetation]\nfeature_map = \"grass2.png\"\n" + species_entry);
  EXPECT_TRUE(has(e, {"grass2.png", "grass type 2"})) << e;
  // A species file with an error inside a placement: the species file and its own line.
  std::ofstream(dir_ / "broken.toml") << "model = \"weber-penn\"\nShape = \"tall\"\n";
  e = error_of(terrain_ +
               "[vegetation]\n[[vegetation.species]]\nbit = 0\nspecies = \"broken.toml\"\nbark = "
               "\"bark\"\nleaf = \"leaf\"\n");
  EXPECT_NE(e.find("broken.toml:"), std::string::npos) << e;
  e = error_of(terrain_ + "[vegetation]\n" + species_entry + "density = 5000\nmin_spacing = 2\n");
  EXPECT_TRUE(has(e, {"density"})) << e;
  e = error_of(terrain_ + "[vegetation]\n" + species_entry + species_entry);
  EXPECT_TRUE(has(e, {"bit 0 names two species"})) << e;
  e = error_of(kMaterials + "[vegetation]\n" + species_entry);
  EXPECT_TRUE(has(e, {"needs a [terrain]"})) << e;
  e = error_of(terrain_ + "[vegetation]\n[[vegetation.species]]\nspecies = \"" + species() + "\"\n");
  EXPECT_TRUE(has(e, {"bit"})) << e;
}

}  // namespace
}  // namespace sylva
