// Issue 16: what a scene reads. Its content hash covers every file it reads (meshes, spectrum
// tables, species), so a checkpoint or golden record of an edited scene is refused; SceneFile::inputs
// lists them (outputs may not be any of them); scene, species and mesh files that are not regular
// files (a FIFO, /dev/zero, a directory) are refused at once instead of hanging.

#include "core/error.h"
#include "scenes/scene_file.h"
#include "scenes/species.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <fstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;

class SceneInputs : public test::TempDirTest {
 protected:
  void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }
  SceneFile load() const { return load_scene_file(dir_ / "scene.toml"); }
};

const char* kMeshScene = R"([materials.m]
type = "diffuse"
reflectance = { file = "refl.csv", column = "r" }
[[meshes]]
file = "tri.obj"
material = "m"
[[trees]]
species = "tree.toml"
bark = "m"
leaf = "m"
)";

TEST_F(SceneInputs, HashCoversEveryFileTheSceneReads) {
  write("scene.toml", kMeshScene);
  write("refl.csv", "lambda_nm,r\n400,0.2\n800,0.4\n");
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  fs::copy_file(SYLVA_SOURCE_DIR "/data/species/quaking_aspen.toml", dir_ / "tree.toml");
  const SceneFile before = load();
  EXPECT_EQ(load().content_hash, before.content_hash) << "the hash is a function of the files";

  // Every file read is an input; the scene file comes first.
  ASSERT_FALSE(before.inputs.empty());
  EXPECT_EQ(before.inputs.front(), dir_ / "scene.toml");
  for (const char* name : {"refl.csv", "tri.obj", "tree.toml"})
    EXPECT_NE(std::find(before.inputs.begin(), before.inputs.end(), dir_ / name), before.inputs.end()) << name;

  // Editing the mesh, the spectrum table or the species changes the hash (each edit undone after).
  const auto edited_hash = [&](const std::string& name, const std::string& text) {
    std::ifstream in(dir_ / name);
    const std::string original((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    write(name, text);
    const std::string hash = load().content_hash;
    write(name, original);
    return hash;
  };
  EXPECT_NE(edited_hash("tri.obj", "v 0 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\n"), before.content_hash);
  EXPECT_NE(edited_hash("refl.csv", "lambda_nm,r\n400,0.2\n800,0.5\n"), before.content_hash);
  std::ifstream species_in(dir_ / "tree.toml");
  const std::string species((std::istreambuf_iterator<char>(species_in)), std::istreambuf_iterator<char>());
  EXPECT_NE(edited_hash("tree.toml", species + "# edited\n"), before.content_hash);
  EXPECT_EQ(load().content_hash, before.content_hash);
}

TEST_F(SceneInputs, SceneOnlyReadingSpeciesKeepsItsHashDefinition) {
  // docs/design.md §8: species files chain first, as before issue 16, so the golden records of
  // scenes that read nothing else keep their scene_hash.
  write("scene.toml",
        "[materials.m]\nreflectance = 0.5\n[[trees]]\nspecies = \"tree.toml\"\nbark = \"m\"\nleaf = \"m\"\n");
  fs::copy_file(SYLVA_SOURCE_DIR "/data/species/quaking_aspen.toml", dir_ / "tree.toml");
  const SceneFile f = load();
  EXPECT_EQ(f.inputs.size(), 2u);
}

TEST_F(SceneInputs, NonRegularFilesAreRefusedAtOnce) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo.toml").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((dir_ / "fifo.obj").c_str(), 0600), 0);
  fs::create_directory(dir_ / "dir.toml");
  const auto start = std::chrono::steady_clock::now();
  const auto message = [](const auto& load_it) {
    try {
      load_it();
    } catch (const ParseError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message([&] { load_scene_file(dir_ / "fifo.toml"); }).find("fifo.toml:0: cannot read scene file: a FIFO"),
            std::string::npos);
  EXPECT_NE(message([&] { load_scene_file(dir_ / "dir.toml"); }).find("cannot read scene file: a directory"),
            std::string::npos);
  EXPECT_NE(message([&] { load_scene_file("/dev/zero"); }).find("cannot read scene file: a device"), std::string::npos);
  EXPECT_NE(message([&] { load_species(dir_ / "fifo.toml"); }).find("cannot read species file: a FIFO"),
            std::string::npos);
  write("scene.toml", "[materials.m]\nreflectance = 0.5\n[[meshes]]\nfile = \"fifo.obj\"\nmaterial = \"m\"\n");
  EXPECT_NE(message([&] { load(); }).find("cannot read mesh: a FIFO"), std::string::npos) << message([&] { load(); });
  write("scene.toml",
        "[materials.m]\nreflectance = 0.5\n[[trees]]\nspecies = \"fifo.toml\"\nbark = \"m\"\nleaf = \"m\"\n");
  EXPECT_NE(message([&] { load(); }).find("cannot read species file: a FIFO"), std::string::npos);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5)) << "nothing may wait for a writer";
}

}  // namespace
}  // namespace sylva
