// The section table and the tree-variant cache (scenes/sections/): every section is named once and
// read in an order that puts what a section uses before it; [[trees]] and [[placements]] of the
// same variant share its prototypes at every level of detail; [vegetation] keeps its own.

#include "core/error.h"
#include "scenes/scene_file.h"
#include "scenes/sections/scene_sections.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace sylva {
namespace {

size_t position_of(std::string_view name) {
  const std::span<const SceneSection> sections = scene_sections();
  for (size_t i = 0; i < sections.size(); ++i)
    if (sections[i].name == name) return i;
  ADD_FAILURE() << "no section " << name;
  return sections.size();
}

TEST(SceneSections, EachSectionOnceAndItsInputsBeforeIt) {
  std::set<std::string_view> names;
  for (const SceneSection& s : scene_sections()) {
    EXPECT_TRUE(names.insert(s.name).second) << s.name;
    EXPECT_NE(s.read, nullptr) << s.name;
  }
  EXPECT_EQ(names.size(), 20u);  // with [sensor]
  // Materials before every user of one; [render] and [camera] before [lod] (the image and view
  // give each tree's range); the [plot] before the tiles of meshes and trees; the terrain before
  // what stands on it; meshes and terrain before the targets that snap onto them.
  for (const char* user :
       {"plot", "meshes", "trees", "leaves", "canopies", "terrain", "grass", "vegetation", "placements", "targets"})
    EXPECT_LT(position_of("materials"), position_of(user)) << user;
  EXPECT_LT(position_of("render"), position_of("lod"));
  EXPECT_LT(position_of("camera"), position_of("lod"));
  EXPECT_LT(position_of("lod"), position_of("trees"));
  for (const char* user : {"meshes", "trees", "leaves", "canopies"}) EXPECT_LT(position_of("plot"), position_of(user));
  EXPECT_LT(position_of("terrain"), position_of("vegetation"));
  EXPECT_LT(position_of("grass"), position_of("vegetation"));
  EXPECT_LT(position_of("terrain"), position_of("targets"));
  EXPECT_LT(position_of("meshes"), position_of("targets"));
}

TEST(SceneSections, UnknownSectionListsTheTableInOrder) {
  std::string expected;
  for (const SceneSection& s : scene_sections()) expected += (expected.empty() ? "" : ", ") + std::string(s.name);
  try {
    parse_scene("[camra]\nposition = [0, -5, 1]\n", "typo.toml", ".");
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(std::string(e.what()),
              "typo.toml:1: unknown key 'camra' in the scene (expected one of: " + expected + ")");
  }
}

// One aspen, seed 1, with the same materials: by [[trees]] (twice) and by a [[placements]] row.
std::string shared_scene(const std::string& extra) {
  const std::string species = std::string(SYLVA_SOURCE_DIR) + "/data/species/quaking_aspen.toml";
  return R"([render]
width = 160
height = 90
[camera]
position = [0, -60, 3]
target = [0, 0, 3]
[materials.bark]
reflectance = 0.3
[materials.leaf]
type = "leaf"
reflectance = 0.4
transmittance = 0.3
[[trees]]
species = ")" +
         species + R"("
bark = "bark"
leaf = "leaf"
quality = 0.2
translate = [0, 0, 0]
[[trees]]
species = ")" +
         species + R"("
bark = "bark"
leaf = "leaf"
quality = 0.2
translate = [0, 150, 0]
[[placements]]
rows = [{ x = 5, y = 400, species = "aspen", seed = 1 }, { x = -5, y = 10, species = "aspen", seed = 1 }]
[placements.species.aspen]
species = ")" +
         species + R"("
bark = "bark"
leaf = "leaf"
quality = 0.2
)" + extra;
}

TEST(TreeVariantCache, TreesAndPlacementsShareOneVariant) {
  const SceneFile f = parse_scene(shared_scene(""), "shared.toml", ".");
  ASSERT_EQ(f.variants.size(), 1u);
  std::set<uint32_t> used;
  for (const Instance& inst : f.scene.instances) {
    used.insert(inst.prototype);
    EXPECT_EQ(inst.variant_id, 1u);
  }
  EXPECT_EQ(used.size(), f.scene.prototypes.size());  // nothing made twice, nothing unused
  EXPECT_EQ(f.scene.instances.size(), 4 * f.scene.prototypes.size());
}

TEST(TreeVariantCache, LevelsOfDetailAreMadeOncePerVariant) {
  const SceneFile f = parse_scene(shared_scene("[lod]\n"), "shared.toml", ".");
  ASSERT_EQ(f.variants.size(), 1u);
  std::set<std::string> names;
  for (const Prototype& p : f.scene.prototypes) EXPECT_TRUE(names.insert(p.name).second) << p.name;
  std::set<uint32_t> used;
  for (const Instance& inst : f.scene.instances) used.insert(inst.prototype);
  // The copies at 10 to 400 m draw reduced levels, each made once, when first drawn (the full
  // tree is made when the variant is, for the [[trees]] that name it).
  size_t levels = 0;
  for (uint32_t i = 0; i < f.scene.prototypes.size(); ++i)
    if (f.scene.prototypes[i].name.find("(lod r2") != std::string::npos) {
      ++levels;
      EXPECT_EQ(used.count(i), 1u) << f.scene.prototypes[i].name;
    }
  EXPECT_GE(levels, 2u);
}

}  // namespace
}  // namespace sylva
