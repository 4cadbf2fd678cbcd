// The class table (Scene::class_names, `id.class`): built-in classes keep their ids, every other
// class's id follows from its name alone, so it is the same whatever the scene's order and in every
// scene of a study; [[meshes]] name their class (a pad, a road) and targets still snap onto them.
// And a copied example still finds the species, tables and meshes it names (core/data_path.h).

#include "core/data_path.h"
#include "core/error.h"
#include "scenes/scene_file.h"
#include "scenes/sections/scene_builder.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace sylva {
namespace {

const std::string kHeader = R"([materials.grey]
reflectance = 0.3
[[meshes]]
name = "ground"
shape = "plane"
size = [100, 100]
material = "grey"
class = "terrain"
[[meshes]]
name = "pad"
shape = "box"
size = [6, 6, 0.4]
translate = [10, 0, 0]
material = "grey"
class = "concrete pad"
)";

std::string target(const std::string& label, float x) {
  return "[[targets]]\nfile = \"targets/vehicle.obj\"\nmaterial = \"grey\"\nlabel = \"" + label + "\"\nposition = [" +
         std::to_string(x) + ", 0, 0]\n";
}

SceneFile parse(const std::string& text) {
  return parse_scene(text, "classes.toml", SYLVA_SOURCE_DIR "/data/examples");
}

TEST(ClassTable, BuiltInIdsAreFixedAndNamedIdsComeFromTheName) {
  EXPECT_EQ(class_id_of("sky"), kClassSky);
  EXPECT_EQ(class_id_of("terrain"), kClassTerrain);
  EXPECT_EQ(class_id_of("grass"), kClassGrass);
  EXPECT_EQ(class_id_of("mesh"), kClassMesh);
  const uint32_t vehicle = class_id_of("vehicle");
  EXPECT_GE(vehicle, kFirstNamedClass);
  EXPECT_LT(vehicle, kMaxClassId);
  EXPECT_NE(class_id_of("vehicles"), vehicle);
  // The definition, pinned: class ids are stored in studies' annotations and must never move.
  EXPECT_EQ(vehicle, kFirstNamedClass + fnv1a64("vehicle") % (kMaxClassId - kFirstNamedClass));
}

TEST(ClassTable, IdsDoNotDependOnTheOrderOfTheScene) {
  const SceneFile a = parse(kHeader + target("vehicle", 0) + target("crate", 10));
  const SceneFile b = parse(kHeader + target("crate", 10) + target("vehicle", 0));
  EXPECT_EQ(a.scene.class_names, b.scene.class_names);
  EXPECT_EQ(a.targets[0].class_id, b.targets[1].class_id);
  EXPECT_EQ(a.targets[0].class_id, class_id_of("vehicle"));
  EXPECT_EQ(a.scene.class_names.at(class_id_of("crate")), "crate");
}

TEST(ClassTable, MeshesNameTheirClassAndTargetsStandOnThem) {
  const SceneFile f = parse(kHeader + target("vehicle", 10) + target("vehicle", 30));
  EXPECT_EQ(f.scene.instances[0].class_id, kClassTerrain);
  EXPECT_EQ(f.scene.instances[1].class_id, class_id_of("concrete pad"));
  EXPECT_EQ(f.scene.class_names.at(class_id_of("concrete pad")), "concrete pad");
  EXPECT_EQ(f.scene.class_names.count(kClassMesh), 1u);  // the built-in row stays
  // The first vehicle stands on the pad (its top 0.4 m above the ground plane at z = 0), the second
  // on the ground.
  EXPECT_NEAR(f.targets[0].position.z, 0.4f, 1e-5f);
  EXPECT_NEAR(f.targets[1].position.z, 0.0f, 1e-5f);
  // A mesh without a class is of class "mesh", as before.
  const SceneFile plain =
      parse("[materials.grey]\nreflectance = 0.3\n[[meshes]]\nshape = \"box\"\nmaterial = \"grey\"\n");
  EXPECT_EQ(plain.scene.instances[0].class_id, kClassMesh);
}

TEST(ClassTable, ACollisionNamesTheFileAndLine) {
  // Two names whose ids collide (found by search): the second is refused where it is given.
  ASSERT_EQ(class_id_of("class 54351"), class_id_of("class 60020"));
  try {
    parse(kHeader + target("class 54351", 0) + target("class 60020", 10));
    ADD_FAILURE() << "no error";
  } catch (const ParseError& e) {
    const std::string m = e.what();
    // The second target's label, line 24 of the scene.
    EXPECT_EQ(m.rfind("classes.toml:24: class 'class 60020' has the id " + std::to_string(class_id_of("class 60020")) +
                          " of class 'class 54351'",
                      0),
              0u)
        << m;
  }
}

class CopiedExample : public test::TempDirTest {};

TEST_F(CopiedExample, FindsItsSpeciesTablesAndMeshesInTheDataFolder) {
  // data/examples/targets.toml names ../species/quaking_aspen.toml, targets_trees.csv (beside it),
  // spectra/*.csv and targets/*.obj (in data/): copied alone into another folder, all still resolve.
  std::ifstream in(SYLVA_SOURCE_DIR "/data/examples/targets.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::ofstream(dir_ / "study.toml") << text.str();
  SceneOptions options;
  options.resolution = std::make_pair(32, 18);
  const SceneFile f = load_scene_file(dir_ / "study.toml", options);
  EXPECT_GE(f.targets.size(), 2u);
  EXPECT_FALSE(f.variants.empty());
}

TEST_F(CopiedExample, AMissingFileNamesWhereItLooked) {
  std::ofstream(dir_ / "lost.toml")
      << "[[trees]]\nspecies = \"../species/no_such_tree.toml\"\nbark = \"a\"\nleaf = \"b\"\n";
  try {
    load_scene_file(dir_ / "lost.toml");
    ADD_FAILURE() << "no error";
  } catch (const ParseError& e) {
    const std::string m = e.what();
    EXPECT_EQ(
        m.rfind((dir_ / "lost.toml").string() + ":2: file not found: ../species/no_such_tree.toml (looked for ", 0), 0u)
        << m;
    EXPECT_NE(m.find((dir_ / "../species/no_such_tree.toml").string()), std::string::npos) << m;
    EXPECT_NE(m.find((data_dir() / "species/no_such_tree.toml").string()), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace sylva
