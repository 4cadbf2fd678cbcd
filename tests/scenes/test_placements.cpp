// [[placements]]: placement lists (CSV files and TOML rows) — variants made once, instances and
// labels per row, determinism at any thread count, and file:line errors for bad rows.

#include "core/error.h"
#include "scenes/placement_list.h"
#include "scenes/scene_file.h"
#include "scenes/sections/scene_builder.h"
#include "tests/support/temp_dir.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <fstream>
#include <string>

namespace sylva {
namespace {

class Placements : public test::TempDirTest {
 protected:
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }

  // The bark and leaf materials and the start of a [[placements]] table, shared by every scene here.
  static constexpr const char* kHeader = R"(
[materials.bark]
reflectance = 0.3
[materials.leaf]
type = "leaf"
reflectance = 0.4
transmittance = 0.3
[[placements]]
)";

  std::string scene(const std::string& list_key) const {
    return kHeader + list_key +
           R"(
[placements.species.aspen]
species = ")" +
           std::string(SYLVA_SOURCE_DIR) +
           R"(/data/species/quaking_aspen.toml"
bark = "bark"
leaf = "leaf"
quality = 0.2
[placements.species.tupelo]
species = ")" +
           std::string(SYLVA_SOURCE_DIR) +
           R"(/data/species/black_tupelo.toml"
bark = "bark"
leaf = "leaf"
quality = 0.2
)";
  }

  SceneFile parse(const std::string& text) { return parse_scene(text, (dir_ / "scene.toml").string(), dir_); }

  std::string error_of(const std::string& text) {
    try {
      parse(text);
    } catch (const ParseError& e) {
      return e.what();
    }
    return "";
  }
};

const std::string kList = R"(# a test list
x, y, species, seed, scale, heading, z
0, 0, aspen, 1, 1.0, 0, 0
10, 0, aspen, 2, 1.2, 90, 0.5

-10, 5, tupelo, 1, 0.8, 45, 0
3, -7, aspen, 1, 1.1, 180, 0
)";

TEST_F(Placements, EachVariantOnceEachRowAnObject) {
  write("trees.csv", kList);
  const SceneFile f = parse(scene("file = \"trees.csv\""));
  // Three distinct (species, seed): aspen 1, aspen 2, tupelo 1, in first-listed order.
  ASSERT_EQ(f.variants.size(), 3u);
  EXPECT_EQ(f.variants[0].seed, 1u);
  EXPECT_EQ(f.variants[1].seed, 2u);
  EXPECT_EQ(f.variants[2].class_id, class_id_of(f.variants[2].name));
  EXPECT_EQ(f.scene.class_names.at(f.variants[0].class_id), f.variants[0].name);
  // One instance per row (these species have one prototype), each row its own object.
  ASSERT_EQ(f.scene.instances.size(), 4u);
  std::vector<uint32_t> objects;
  for (const Instance& inst : f.scene.instances) objects.push_back(inst.object_id);
  EXPECT_EQ(objects, (std::vector<uint32_t>{1, 2, 3, 4}));
  EXPECT_EQ(f.scene.instances[0].prototype, f.scene.instances[3].prototype) << "aspen seed 1 is instanced";
  EXPECT_EQ(f.scene.instances[1].variant_id, 2u);
  // Row 2: at (10, 0, 0.5), scale 1.2, heading 90 (+Y turned to the east).
  const Mat4& m = f.scene.instances[1].world_from_object;
  EXPECT_EQ(Vec3(m[3]), Vec3(10, 0, 0.5f));
  const Vec3 forward(m * Vec4(0, 1, 0, 0));
  EXPECT_NEAR(forward.x, 1.2f, 1e-6f);
  EXPECT_NEAR(forward.y, 0.0f, 1e-6f);
  EXPECT_NEAR(Vec3(m * Vec4(0, 0, 1, 0)).z, 1.2f, 1e-6f);
}

TEST_F(Placements, TomlRowsEqualTheCsvAndAnyThreadCountGivesTheSameScene) {
  write("trees.csv", kList);
  const SceneFile csv = parse(scene("file = \"trees.csv\""));
  const SceneFile rows = parse(scene(R"(rows = [
  { x = 0, y = 0, species = "aspen", seed = 1, scale = 1.0, heading = 0 },
  { x = 10, y = 0, z = 0.5, species = "aspen", seed = 2, scale = 1.2, heading = 90 },
  { x = -10, y = 5, species = "tupelo", seed = 1, scale = 0.8, heading = 45 },
  { x = 3, y = -7, species = "aspen", seed = 1, scale = 1.1, heading = 180 },
])"));
  SceneFile serial;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial = parse(scene("file = \"trees.csv\""));
  }
  for (const SceneFile* other : {&rows, static_cast<const SceneFile*>(&serial)}) {
    ASSERT_EQ(other->scene.instances.size(), csv.scene.instances.size());
    for (size_t i = 0; i < csv.scene.instances.size(); ++i) {
      const Instance &a = csv.scene.instances[i], &b = other->scene.instances[i];
      EXPECT_EQ(a.prototype, b.prototype);
      EXPECT_EQ(a.object_id, b.object_id);
      EXPECT_EQ(a.class_id, b.class_id);
      EXPECT_EQ(a.variant_id, b.variant_id);
      EXPECT_EQ(a.world_from_object, b.world_from_object);
    }
    ASSERT_EQ(other->scene.prototypes.size(), csv.scene.prototypes.size());
    for (size_t p = 0; p < csv.scene.prototypes.size(); ++p) {
      EXPECT_EQ(other->scene.prototypes[p].triangles.positions, csv.scene.prototypes[p].triangles.positions);
      EXPECT_EQ(other->scene.prototypes[p].leaves.corners, csv.scene.prototypes[p].leaves.corners);
    }
  }
  EXPECT_EQ(serial.content_hash, csv.content_hash);
}

TEST_F(Placements, BadRowsAreFileLineErrors) {
  const std::string header = "x,y,species,seed,scale,heading\n";
  const auto list_error = [&](const std::string& text) {
    write("bad.csv", text);
    return error_of(scene("file = \"bad.csv\""));
  };
  const std::string at = (dir_ / "bad.csv").string();
  EXPECT_NE(list_error(header + "0,0,aspen,1,1,0\n1,x,aspen,1,1,0\n").find(at + ":3: y: expected a number"),
            std::string::npos);
  EXPECT_NE(list_error(header + "0,0,oak,1,1,0\n").find(at + ":2: unknown species 'oak'"), std::string::npos);
  EXPECT_NE(list_error(header + "0,0,aspen,1,0,0\n").find(at + ":2: scale"), std::string::npos);
  EXPECT_NE(list_error(header + "0,0,aspen,-1,1,0\n").find(at + ":2: seed"), std::string::npos);
  EXPECT_NE(list_error(header + "0,0,aspen,1,1\n").find(at + ":2: expected 6 fields"), std::string::npos);
  EXPECT_NE(
      list_error("# only a comment\nx,y,species,seed,scale\n").find(at + ":2: the header needs a column 'heading'"),
      std::string::npos);
  EXPECT_NE(list_error("x,y,kind,seed,scale,heading\n").find(at + ":1: unknown column 'kind'"), std::string::npos);
  EXPECT_NE(list_error("").find(at + ":1: the placement list has no header"), std::string::npos);
  EXPECT_NE(list_error(header + "1e9,0,aspen,1,1,0\n").find(at + ":2: x"), std::string::npos);
  // A missing list, and a TOML row naming an unknown species.
  EXPECT_NE(error_of(scene("file = \"missing.csv\"")).find("missing.csv"), std::string::npos);
  EXPECT_NE(
      error_of(scene("rows = [\n  { x = 0, y = 0, species = \"oak\" },\n]")).find("scene.toml:10: unknown species"),
      std::string::npos);
}

TEST_F(Placements, SpeciesFileErrorsNameTheSpeciesFile) {
  write("broken.toml", "model = \"weber-penn\"\nShape = 3\nLevels = banana\n");
  write("trees.csv", "x,y,species,seed,scale,heading\n0,0,bad,1,1,0\n");
  const std::string text = std::string(kHeader) + R"(file = "trees.csv"
[placements.species.bad]
species = "broken.toml"
bark = "bark"
leaf = "leaf"
)";
  const std::string e = error_of(text);
  EXPECT_NE(e.find((dir_ / "broken.toml").string() + ":"), std::string::npos) << e;
}

TEST_F(Placements, StreamedReaderCallsBackPerRowWithLineNumbers) {
  write("trees.csv", kList);
  std::vector<int> lines;
  std::vector<std::string> species;
  for_each_placement_row(dir_ / "trees.csv", 1e7f, [&](const PlacementRow& r, int line) {
    lines.push_back(line);
    species.emplace_back(r.species);
  });
  EXPECT_EQ(lines, (std::vector<int>{3, 4, 6, 7}));
  EXPECT_EQ(species, (std::vector<std::string>{"aspen", "aspen", "tupelo", "aspen"}));
}

}  // namespace
}  // namespace sylva
