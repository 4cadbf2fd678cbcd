// TREE-MAKER species in scenes: `.tmpl` files and `model = "treemaker"` TOML species through the
// species registry, flowers as their own material (a second prototype placed with the tree), and
// the template's colours as default materials (Smits up-sampling).

#include "core/error.h"
#include "scenes/scene_file.h"
#include "scenes/species.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace sylva {
namespace {

const std::filesystem::path kSource = SYLVA_SOURCE_DIR;

const Material& material_of(const SceneFile& f, uint32_t id) { return f.scene.materials.at(id); }

TEST(TreeMakerScene, TmplFilesAreSpecies) {
  const Species s = load_species(kSource / "data" / "species" / "dogwood.tmpl");
  EXPECT_EQ(s.name, "dogwood");
  ASSERT_TRUE(std::holds_alternative<TreeMakerTemplate>(s.model));
  EXPECT_EQ(std::get<TreeMakerTemplate>(s.model).iterations, 13);
  const TreeModel a = make_species_model(s, 4);
  const TreeModel b = make_treemaker_tree(std::get<TreeMakerTemplate>(s.model), 4);
  EXPECT_EQ(a.sections.positions, b.sections.positions);
  EXPECT_EQ(a.leaves.material, b.leaves.material);
}

TEST(TreeMakerScene, TomlSpeciesNamesATemplate) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sylva_test_treemaker_scene";
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(kSource / "data" / "species" / "dogwood.tmpl", dir / "dogwood.tmpl",
                             std::filesystem::copy_options::overwrite_existing);
  std::ofstream(dir / "small_dogwood.toml") << "model = \"treemaker\"\nname = \"Small dogwood\"\n"
                                               "template = \"dogwood.tmpl\"\nunit_m = 0.015\n";
  const Species s = load_species(dir / "small_dogwood.toml");
  EXPECT_EQ(s.name, "Small dogwood");
  const TreeMakerTemplate& t = std::get<TreeMakerTemplate>(s.model);
  EXPECT_EQ(t.iterations, 13);
  EXPECT_FLOAT_EQ(t.unit_m, 0.015f);
  // Half the unit, half the tree.
  const Species full = load_species(dir / "dogwood.tmpl");
  const TreeModel small = make_species_model(s, 2), big = make_species_model(full, 2);
  EXPECT_NEAR(small.stems.length_m[0], 0.5f * big.stems.length_m[0], 1e-5f);

  std::ofstream(dir / "bad.toml") << "model = \"treemaker\"\ntemplate = \"dogwood.tmpl\"\nunit = 0.015\n";
  try {
    load_species(dir / "bad.toml");
    FAIL() << "accepted an unknown key";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml:3"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "missing.toml") << "model = \"treemaker\"\ntemplate = \"nowhere.tmpl\"\n";
  EXPECT_THROW(load_species(dir / "missing.toml"), ParseError);
}

TEST(TreeMakerScene, TheSceneHashCoversATemplateNamedByATomlSpecies) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sylva_test_treemaker_hash";
  std::filesystem::create_directories(dir);
  const std::string tmpl = [] {
    std::ifstream in(kSource / "data" / "species" / "dogwood.tmpl", std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }();
  std::ofstream(dir / "d.toml") << "model = \"treemaker\"\ntemplate = \"d.tmpl\"\n";
  const std::string scene = "[[trees]]\nspecies = \"d.toml\"\n";
  std::ofstream(dir / "d.tmpl", std::ios::binary) << tmpl;
  const std::string before = parse_scene(scene, "s.toml", dir).content_hash;
  std::ofstream(dir / "d.tmpl", std::ios::binary) << tmpl << "\n# changed\n";
  EXPECT_NE(parse_scene(scene, "s.toml", dir).content_hash, before);
}

TEST(TreeMakerScene, FlowersAreASecondPrototypeWithTheTemplateColours) {
  const SceneFile f = parse_scene(R"(
[[trees]]
species = "../species/dogwood.tmpl"
seed = 1
translate = [2, 0, 0]
)",
                                  "dogwood.toml", kSource / "data" / "examples");
  ASSERT_EQ(f.scene.prototypes.size(), 2u);
  ASSERT_EQ(f.scene.instances.size(), 2u);
  EXPECT_EQ(f.scene.instances[0].world_from_object, f.scene.instances[1].world_from_object);
  const Prototype& tree = f.scene.prototypes[0];
  const Prototype& flowers = f.scene.prototypes[1];
  EXPECT_GT(tree.triangles.triangles.size(), 1000u);
  EXPECT_TRUE(flowers.triangles.triangles.empty());
  const TreeModel model = make_treemaker_tree(
      std::get<TreeMakerTemplate>(load_species(kSource / "data" / "species" / "dogwood.tmpl").model), 1);
  EXPECT_EQ(tree.leaves.size() + flowers.leaves.size(), model.leaves.size());
  EXPECT_GT(flowers.leaves.size(), 200u);

  // White bracts, green leaves, brown bark — reflectances in [0, 1].
  const auto& petal = std::get<LeafMaterial>(material_of(f, flowers.leaf_material));
  EXPECT_NEAR(petal.reflectance_front.spectrum.eval(550.0f), 0.95f, 0.01f);
  EXPECT_LE(petal.reflectance_front.spectrum.max_value(), 1.0f);
  const auto& leaf = std::get<LeafMaterial>(material_of(f, tree.leaf_material));
  EXPECT_GT(leaf.reflectance_front.spectrum.eval(540.0f), 3.0f * leaf.reflectance_front.spectrum.eval(450.0f));
  EXPECT_GT(leaf.reflectance_front.spectrum.eval(540.0f), 3.0f * leaf.reflectance_front.spectrum.eval(650.0f));
  const auto& bark = std::get<DiffuseMaterial>(material_of(f, tree.triangle_material));
  EXPECT_GT(bark.reflectance.spectrum.eval(650.0f), 2.0f * bark.reflectance.spectrum.eval(450.0f));
  EXPECT_LT(bark.reflectance.spectrum.max_value(), 0.5f);
}

TEST(TreeMakerScene, SceneMaterialsOverrideTheTemplate) {
  const SceneFile f = parse_scene(R"(
[materials.grey]
reflectance = 0.5
[materials.petal]
type = "leaf"
reflectance = 0.7
transmittance = 0.2

[[trees]]
species = "../species/dogwood.tmpl"
seed = 1
bark = "grey"
leaf = "grey"
flower = "petal"
)",
                                  "dogwood.toml", kSource / "data" / "examples");
  ASSERT_EQ(f.scene.prototypes.size(), 2u);
  EXPECT_EQ(f.scene.material_names[f.scene.prototypes[0].triangle_material], "grey");
  EXPECT_EQ(f.scene.material_names[f.scene.prototypes[0].leaf_material], "grey");
  EXPECT_EQ(f.scene.material_names[f.scene.prototypes[1].leaf_material], "petal");
  EXPECT_EQ(f.scene.materials.size(), 2u);  // no template materials were made
}

TEST(TreeMakerScene, OtherModelsStillNeedTheirMaterialsAndHaveNoFlowers) {
  const auto error = [](const std::string& text) -> std::string {
    try {
      parse_scene(text, "scene.toml", kSource / "data" / "examples");
    } catch (const ParseError& e) {
      return e.what();
    }
    return "";
  };
  const std::string grey = "[materials.grey]\nreflectance = 0.5\n";
  EXPECT_NE(error(grey + "[[trees]]\nspecies = \"../species/quaking_aspen.toml\"\nleaf = \"grey\"\n").find("bark"),
            std::string::npos);
  EXPECT_NE(error(grey + "[[trees]]\nspecies = \"../species/quaking_aspen.toml\"\nbark = \"grey\"\nleaf = "
                         "\"grey\"\nflower = \"grey\"\n")
                .find("scene.toml:7: 'flower' is for models with flowers"),
            std::string::npos);
}

TEST(TreeMakerScene, ExampleSceneParses) {
  const SceneFile f = load_scene_file(kSource / "data" / "examples" / "dogwood.toml");
  EXPECT_GE(f.scene.prototypes.size(), 4u);
}

}  // namespace
}  // namespace sylva
