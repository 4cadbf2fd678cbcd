// `sylva render` end to end: outputs and their header, errors without partial output,
// determinism across --threads, and SIGINT → checkpoint → --resume equal to an uninterrupted run.

#include "core/image.h"
#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <map>
#include <sstream>

#include <signal.h>

#include <chrono>
#include <cmath>
#include <thread>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::read_text;
using test::run_sylva;

TEST(CliRender, DefaultSceneWritesExrAndPng) {
  const fs::path dir = fresh_dir("cli_default");
  const auto r =
      run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + (dir / "out.exr").string() +
                    "' --png '" + (dir / "out.png").string() + "' --res 48x27 --spp 4 --quiet",
                dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;  // --quiet
  ASSERT_TRUE(fs::exists(dir / "out.png"));
  const Image img = read_exr(dir / "out.exr");
  EXPECT_EQ(img.width, 48);
  EXPECT_EQ(img.height, 27);
  for (const char* c : {"R", "G", "B", "nir.Y", "var.R", "var.nir.Y", "albedo.G", "albedo.nir.Y", "Z", "N.X", "N.Y",
                        "N.Z", "id.instance", "id.object"})
    EXPECT_GE(img.find_channel(c), 0) << c;
  EXPECT_EQ(img.types[img.find_channel("id.instance")], PixelType::UInt);
  EXPECT_EQ(img.attribute("sylva:spp"), "4");
  EXPECT_EQ(img.attribute("sylva:seed"), "1");
  EXPECT_EQ(img.attribute("sylva:bands"), "rgb,nir");
  EXPECT_FALSE(img.attribute("sylva:scene_hash").empty());
  // No temporary or checkpoint files are left behind.
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    EXPECT_TRUE(name == "out.exr" || name == "out.png" || name == "out.json" || name.ends_with(".txt")) << name;
  }
  // Labels: the objects scene (data/examples/objects.toml) has 10 instances; the target box is object 1, the trees
  // object 2.
  const int inst = img.find_channel("id.instance"), obj = img.find_channel("id.object");
  float max_instance = 0;
  bool target = false, tree = false;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      max_instance = std::max(max_instance, img.at(x, y, inst));
      target = target || img.at(x, y, obj) == 1.0f;
      tree = tree || img.at(x, y, obj) == 2.0f;
    }
  EXPECT_GE(max_instance, 5.0f);
  EXPECT_LE(max_instance, 10.0f);
  EXPECT_TRUE(target);
  EXPECT_TRUE(tree);
  // Radiometric sanity: sky and ground are lit, nothing is negative or NaN in the band channels.
  const int g = img.find_channel("G"), n = img.find_channel("nir.Y");
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      ASSERT_TRUE(std::isfinite(img.at(x, y, g)));
      ASSERT_GE(img.at(x, y, n), 0.0f);
    }
}

// A 2×1 8-bit grey baseline TIFF (uncompressed, one strip), written byte by byte: the test binary
// links no image library that writes TIFF.
void write_grey_tiff(const fs::path& file, uint8_t a, uint8_t b) {
  std::string bytes = std::string("II*\0", 4);
  const auto u16 = [&](uint16_t v) { bytes.append({static_cast<char>(v & 0xff), static_cast<char>(v >> 8)}); };
  const auto u32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  };
  u32(8);                                                               // the first directory
  const std::array<std::array<uint32_t, 3>, 9> entries{{{256, 3, 2},    // ImageWidth
                                                        {257, 3, 1},    // ImageLength
                                                        {258, 3, 8},    // BitsPerSample
                                                        {259, 3, 1},    // Compression: none
                                                        {262, 3, 1},    // Photometric: black is zero
                                                        {273, 4, 122},  // StripOffsets: after the directory
                                                        {277, 3, 1},    // SamplesPerPixel
                                                        {278, 3, 1},    // RowsPerStrip
                                                        {279, 4, 2}}};  // StripByteCounts
  u16(static_cast<uint16_t>(entries.size()));
  for (const auto& [tag, type, value] : entries) {
    u16(static_cast<uint16_t>(tag));
    u16(static_cast<uint16_t>(type));
    u32(1);
    if (type == 3) {
      u16(static_cast<uint16_t>(value));
      u16(0);
    } else {
      u32(value);
    }
  }
  u32(0);  // no next directory
  bytes.push_back(static_cast<char>(a));
  bytes.push_back(static_cast<char>(b));
  std::ofstream(file, std::ios::binary) << bytes;
}

// A render writes its EXR and PNG with OpenEXR and libpng, and PNG and EXR files are read with
// them: OpenImageIO (some 250 libraries, a quarter of a second at start) is loaded, through its
// module, only to read another format (core/image_reader.h). glibc's loader lists every object it
// loads under LD_DEBUG=files.
TEST(CliRender, OpenImageIoIsLoadedOnlyForOtherFormats) {
  const fs::path dir = fresh_dir("cli_oiio_module");
  write_grey_tiff(dir / "a.tif", 10, 200);
  const auto compare = [&](const std::string& name) {
    return run_sylva("compare '" + (dir / name).string() + "' '" + (dir / name).string() +
                         "' --fail 0 --fail-percent 0 --allow-same-seed",
                     dir);
  };
  setenv("LD_DEBUG", "files", 1);
  const auto render =
      run_sylva("render '" SYLVA_SOURCE_DIR "/golden/scenes/ground_sky.toml' -o '" + (dir / "a.exr").string() +
                    "' --png '" + (dir / "a.png").string() + "' --res 16x9 --spp 1 --quiet",
                dir);
  const auto exr = compare("a.exr"), png = compare("a.png"), tiff = compare("a.tif");
  unsetenv("LD_DEBUG");
  ASSERT_EQ(render.exit_code, 0) << render.err;
  ASSERT_EQ(exr.exit_code, 0) << exr.err;
  ASSERT_EQ(png.exit_code, 0) << png.err;
  ASSERT_EQ(tiff.exit_code, 0) << tiff.err;
  EXPECT_NE(render.err.find("libOpenEXR"), std::string::npos);  // the loader's list is there
  EXPECT_NE(render.err.find("libpng"), std::string::npos);
  EXPECT_EQ(render.err.find("libOpenImageIO"), std::string::npos);
  EXPECT_EQ(exr.err.find("libOpenImageIO"), std::string::npos);
  EXPECT_EQ(png.err.find("libOpenImageIO"), std::string::npos);
  EXPECT_NE(tiff.err.find("libsylva_oiio.so"), std::string::npos);
  EXPECT_NE(tiff.err.find("libOpenImageIO"), std::string::npos);
  EXPECT_NE(tiff.out.find("Y "), std::string::npos) << tiff.out;  // its one channel was compared
}

TEST(CliRender, BadSceneFailsWithFileLineAndNoOutput) {
  const fs::path dir = fresh_dir("cli_bad");
  {
    std::ofstream f(dir / "bad.toml");
    f << "[camera]\nposition = [0, -5, 1]\n\n[sun]\nelevation = \"high\"\n";
  }
  const auto r = run_sylva("render '" + (dir / "bad.toml").string() + "' -o '" + (dir / "out.exr").string() + "'", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.toml:5: 'elevation' must be a number"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.exr"));
  const auto missing =
      run_sylva("render '" + (dir / "nope.toml").string() + "' -o '" + (dir / "o.exr").string() + "'", dir);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("nope.toml:0: cannot open scene file"), std::string::npos) << missing.err;
  const auto bad_res = run_sylva(
      "render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + (dir / "o.exr").string() + "' --res 12by4",
      dir);
  EXPECT_EQ(bad_res.exit_code, 2);
  EXPECT_NE(bad_res.err.find("--res"), std::string::npos);
  const auto bad_band = run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" +
                                      (dir / "o.exr").string() + "' --bands rgb,xray --res 8x8",
                                  dir);
  EXPECT_EQ(bad_band.exit_code, 2);
  EXPECT_NE(bad_band.err.find("unknown band 'xray'"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "o.exr"));
}

TEST(CliRender, BitIdenticalFilesAtAnyThreadCount) {
  const fs::path dir = fresh_dir("cli_threads");
  const std::string common = " --res 40x24 --spp 3 --quiet --bands rgb,nir,S2A_B8";
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + (dir / "t1.exr").string() +
                          "' --threads 1" + common,
                      dir)
                .exit_code,
            0);
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + (dir / "t2.exr").string() +
                          "' --threads 2" + common,
                      dir)
                .exit_code,
            0);
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + (dir / "t3.exr").string() +
                          "' --threads 3" + common,
                      dir)
                .exit_code,
            0);
  EXPECT_EQ(read_text(dir / "t1.exr"), read_text(dir / "t2.exr"));
  EXPECT_EQ(read_text(dir / "t1.exr"), read_text(dir / "t3.exr"));
  // A different seed gives a different image.
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + (dir / "s2.exr").string() +
                          "' --seed 2" + common,
                      dir)
                .exit_code,
            0);
  EXPECT_NE(read_text(dir / "t1.exr"), read_text(dir / "s2.exr"));
}

// --isa caps Embree's kernels: the header names the set that ran, a capped render is bit-identical
// at any thread count, and the processor's widest kernels agree with the narrowest statistically.
TEST(CliRender, EmbreeIsaIsRecordedAndAgreesStatistically) {
  const fs::path dir = fresh_dir("cli_isa");
  const std::string scene = "render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' --res 40x24 --quiet -o '";
  for (const char* run : {"n.exr' --spp 64 --seed 1 --isa native", "c1.exr' --spp 64 --seed 2 --isa sse2 --threads 1",
                          "c2.exr' --spp 64 --seed 2 --isa sse2 --threads 2"}) {
    const auto r = run_sylva(scene + (dir / run).string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const std::string native = read_exr(dir / "n.exr").attribute("sylva:embree_isa");
  EXPECT_TRUE(native == "sse2" || native == "sse4.2" || native == "avx" || native == "avx2" || native == "avx512")
      << native;
  EXPECT_EQ(read_exr(dir / "c1.exr").attribute("sylva:embree_isa"), "sse2");
  EXPECT_EQ(read_text(dir / "c1.exr"), read_text(dir / "c2.exr"));
  const auto cmp = run_sylva("compare '" + (dir / "n.exr").string() + "' '" + (dir / "c1.exr").string() + "'", dir);
  EXPECT_EQ(cmp.exit_code, 0) << cmp.out << cmp.err;
  const auto bad = run_sylva(scene + (dir / "x.exr").string() + "' --isa avx3", dir);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("--isa"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

TEST(CliRender, InterruptThenResumeEqualsUninterrupted) {
  const fs::path dir = fresh_dir("cli_resume");
  const std::string common = " --res 160x90 --spp 320 --quiet --threads 2";
  const fs::path out = dir / "int.exr", log = dir / "child.txt";
  // Start a render and interrupt it with SIGINT once it reports that rendering is under way.
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string cmd = std::string(SYLVA_BINARY) +
                            " render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + out.string() +
                            "' --res 160x90 --spp 320 --threads 2";
    ::execl("/bin/sh", "sh", "-c", ("exec " + cmd + " 2>'" + log.string() + "'").c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  for (int i = 0; i < 600 && read_text(log).find("scene:") == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 130) << "the render must still be running 300 ms in; " << read_text(log);
  EXPECT_NE(read_text(log).find("interrupted: checkpoint with"), std::string::npos) << read_text(log);
  EXPECT_FALSE(fs::exists(out)) << "no output from an interrupted render";
  ASSERT_TRUE(fs::exists(out.string() + ".checkpoint"));
  const auto resumed = run_sylva(
      "render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + out.string() + "' --resume" + common, dir);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_FALSE(fs::exists(out.string() + ".checkpoint"));
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + (dir / "full.exr").string() +
                          "'" + common,
                      dir)
                .exit_code,
            0);
  EXPECT_EQ(read_text(out), read_text(dir / "full.exr"));
  // Resuming a different render is refused.
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + out.string() + "'" + common +
                          " --checkpoint-minutes 0",
                      dir)
                .exit_code,
            0);
  const auto wrong = run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" +
                                   (dir / "none.exr").string() + "' --resume" + common,
                               dir);
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("no checkpoint"), std::string::npos) << wrong.err;
}

// `sylva export` of the objects example scene to DIR/OBJ_NAME, with `options` after it.
test::CommandResult export_objects(const fs::path& dir, const std::string& obj_name, const std::string& options = "") {
  return run_sylva(
      "export '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' --obj '" + (dir / obj_name).string() + "'" + options,
      dir);
}

TEST(CliExport, FlattensTheSceneToObj) {
  const fs::path dir = fresh_dir("cli_export");
  const auto r = export_objects(dir, "scene.obj", " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string obj = read_text(dir / "scene.obj");
  // The objects scene: 2522 instanced triangles + 27000 leaf quads as two triangles each.
  size_t faces = 0;
  for (size_t p = obj.find("\nf "); p != std::string::npos; p = obj.find("\nf ", p + 1)) ++faces;
  EXPECT_EQ(faces, 2522u + 2u * 27000u);
  EXPECT_NE(r.out.find("--vp"), std::string::npos) << r.out;  // the matching pathtracer camera
}

// The material library: one material per part, each part's faces under its `usemtl`; diffuse
// colours from the spectra (a constant reflectance keeps its value in every channel, the red paint
// is red); the leaf part's opacity map is the leaf outline (an oval covers π/4 of its quad).
TEST(CliExport, WritesMaterialsAndLeafOutlines) {
  const fs::path dir = fresh_dir("cli_export_materials");
  const auto r = export_objects(dir, "scene.obj");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string obj = read_text(dir / "scene.obj");
  const std::string mtl = read_text(dir / "scene.mtl");
  EXPECT_NE(obj.find("mtllib scene.mtl\n"), std::string::npos);
  std::map<std::string, std::string> materials;  // name → its statements
  for (size_t p = mtl.find("newmtl "); p != std::string::npos;) {
    const size_t end = mtl.find("newmtl ", p + 1);
    const std::string block = mtl.substr(p, end == std::string::npos ? std::string::npos : end - p);
    materials[block.substr(7, block.find('\n') - 7)] = block;
    p = end;
  }
  size_t groups = 0;
  for (size_t p = obj.find("\nusemtl "); p != std::string::npos; p = obj.find("\nusemtl ", p + 1), ++groups) {
    const std::string name = obj.substr(p + 8, obj.find('\n', p + 1) - p - 8);
    EXPECT_EQ(materials.count(name), 1u) << name;
  }
  EXPECT_EQ(groups, materials.size());
  auto kd = [&](const std::string& name) {
    std::istringstream in(materials.at(name).substr(materials.at(name).find("Kd ") + 3));
    std::array<float, 3> c{};
    in >> c[0] >> c[1] >> c[2];
    return c;
  };
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(kd("concrete")[k], 0.35f, 1e-3f);
  EXPECT_GT(kd("paint")[0], 2.0f * kd("paint")[1]);
  EXPECT_GT(kd("paint")[1], kd("paint")[2] * 0.9f);

  ASSERT_EQ(materials.count("leaf.oval"), 1u);
  EXPECT_NE(materials["leaf.oval"].find("map_d scene.oval.ppm"), std::string::npos) << materials["leaf.oval"];
  EXPECT_NE(materials["leaf.oval"].find("Tf 1 1 1"), std::string::npos);
  const std::string ppm = read_text(dir / "scene.oval.ppm");
  const std::string header = "P6\n256 256\n255\n";
  ASSERT_EQ(ppm.size(), header.size() + 3 * 256 * 256);
  EXPECT_EQ(ppm.substr(0, header.size()), header);
  size_t inside = 0;
  for (size_t i = header.size(); i < ppm.size(); i += 3) inside += static_cast<unsigned char>(ppm[i]) == 255;
  EXPECT_NEAR(static_cast<double>(inside) / (256 * 256), 3.14159265 / 4.0, 0.005);
  EXPECT_NE(obj.find("\nvt 1 1\n"), std::string::npos);  // leaf corners carry their quad coordinates

  // Geometry only: no library, no maps, no texture coordinates.
  const auto plain = export_objects(dir, "plain.obj", " --no-materials -q");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_FALSE(fs::exists(dir / "plain.mtl"));
  EXPECT_FALSE(fs::exists(dir / "plain.oval.ppm"));
  EXPECT_EQ(read_text(dir / "plain.obj").find("\nvt "), std::string::npos);
}

// Every file the export would write is checked before the scene is flattened: a directory where an
// outline map would go stops it with nothing written.
TEST(CliExport, ChecksEveryOutputBeforeWriting) {
  const fs::path dir = fresh_dir("cli_export_outputs");
  fs::create_directory(dir / "scene.oval.ppm");
  const auto r = export_objects(dir, "scene.obj");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("scene.oval.ppm"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "scene.obj"));
  EXPECT_FALSE(fs::exists(dir / "scene.mtl"));
}

TEST(CliExport, PolygonisesHalfSpaceCrowns) {
  // A Fournier–Grindal tree in two places: its solids polygonised once, placed twice.
  const fs::path dir = fresh_dir("cli_export_crowns");
  const std::string species = (fs::path(SYLVA_SOURCE_DIR) / "data" / "species" / "fg_conifer.toml").string();
  {
    std::ofstream scene(dir / "s.toml");
    scene << "[[trees]]\nspecies = \"" << species
          << "\"\ninstances = [{ translate = [0, 0, 0] }, { translate = [5, 0, 0] }]\n";
  }
  const auto r =
      run_sylva("export '" + (dir / "s.toml").string() + "' --obj '" + (dir / "s.obj").string() + "' -q", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto tree = run_sylva("tree '" + species + "' --obj '" + (dir / "tree.obj").string() + "'", dir);
  ASSERT_EQ(tree.exit_code, 0) << tree.err;
  const auto faces = [](const std::string& obj) {
    size_t n = 0;
    for (size_t p = obj.find("\nf "); p != std::string::npos; p = obj.find("\nf ", p + 1)) ++n;
    return n;
  };
  const size_t one = faces(read_text(dir / "tree.obj"));
  EXPECT_GT(one, 1000u);
  EXPECT_EQ(faces(read_text(dir / "s.obj")), 2 * one);
}

TEST(CliRender, HelpListsTheOptions) {
  const fs::path dir = fresh_dir("cli_help");
  const auto r = run_sylva("render --help", dir);
  EXPECT_EQ(r.exit_code, 0);
  for (const char* opt : {"--spp", "--res", "--threads", "--seed", "--bands", "--png", "--resume"})
    EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
}

}  // namespace
}  // namespace sylva
