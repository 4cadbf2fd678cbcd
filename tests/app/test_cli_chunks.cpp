// `sylva render --chunk i/N` + `sylva merge` end to end: merged EXRs are byte-identical to a
// single-process render for 1, 2, 3 and 7 chunks by samples and by tiles; foreign, missing and
// duplicated parts are refused naming the file; --partial previews. And `sylva render --frames`:
// one EXR per frame at wind time frame/fps, skipping frames already rendered.

#include "core/image.h"
#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <fstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::q;
using test::read_text;
using test::run_sylva;

// 7 spp and 20 rows give every one of 7 chunks some work, split unevenly.
const std::string kCommon = " --res 30x20 --spp 7 --quiet --threads 2";

// Renders all `n` chunks of the small objects scene into dir/<tag>.<i>.part; returns the merge arguments.
std::string render_chunks(const fs::path& dir, const std::string& tag, int n, const std::string& split,
                          const std::string& extra = "") {
  std::string parts;
  for (int i = n - 1; i >= 0; --i) {
    const fs::path part = dir / (tag + "." + std::to_string(i) + ".part");
    const auto r = run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o " + q(part) + " --chunk " +
                                 std::to_string(i) + "/" + std::to_string(n) + " --split " + split + kCommon + extra,
                             dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    parts += ' ';
    parts += q(part);
  }
  return parts;
}

TEST(CliChunks, MergeEqualsSingleRenderByteForByte) {
  const fs::path dir = fresh_dir("cli_chunks");
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o " + q(dir / "single.exr") +
                          " --png " + q(dir / "single.png") + kCommon,
                      dir)
                .exit_code,
            0);
  const std::string single = read_text(dir / "single.exr"), single_png = read_text(dir / "single.png");
  ASSERT_FALSE(single.empty());
  for (const std::string split : {"samples", "tiles"})
    for (const int n : {1, 2, 3, 7}) {
      const std::string tag = split + std::to_string(n);
      const std::string parts = render_chunks(dir, tag, n, split);
      const fs::path out = dir / (tag + ".exr"), png = dir / (tag + ".png");
      const auto r = run_sylva("merge" + parts + " -o " + q(out) + " --png " + q(png) + " --quiet", dir);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      EXPECT_TRUE(read_text(out) == single) << n << " chunks by " << split << ": EXR differs";
      EXPECT_TRUE(read_text(png) == single_png) << n << " chunks by " << split << ": PNG differs";
    }
  // A different seed's chunks merge to a different image (the comparison can fail).
  const std::string parts = render_chunks(dir, "seed2", 2, "samples", " --seed 2");
  ASSERT_EQ(run_sylva("merge" + parts + " -o " + q(dir / "seed2.exr") + " --quiet", dir).exit_code, 0);
  EXPECT_NE(read_text(dir / "seed2.exr"), single);
}

// Denoising runs after the merge (docs/denoise.md): parts rendered with --features and merged with
// --denoise give the bytes of one `render --denoise`, by samples and by tiles; parts without the
// features are refused.
TEST(CliChunks, MergeDenoiseEqualsRenderDenoiseByteForByte) {
  const fs::path dir = fresh_dir("cli_chunks_denoise");
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o " + q(dir / "single.exr") +
                          " --png " + q(dir / "single.png") + " --denoise" + kCommon,
                      dir)
                .exit_code,
            0);
  const std::string single = read_text(dir / "single.exr"), single_png = read_text(dir / "single.png");
  ASSERT_FALSE(single.empty());
  ASSERT_GE(read_exr(dir / "single.exr").find_channel("noisy.R"), 0);
  for (const auto& [split, n] : {std::pair<std::string, int>{"samples", 3}, {"tiles", 2}}) {
    const std::string tag = split + std::to_string(n);
    const std::string parts = render_chunks(dir, tag, n, split, " --features");
    const fs::path out = dir / (tag + ".exr"), png = dir / (tag + ".png");
    const auto r = run_sylva("merge" + parts + " -o " + q(out) + " --png " + q(png) + " --denoise --quiet", dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(read_text(out) == single) << n << " chunks by " << split << ": denoised EXR differs";
    EXPECT_TRUE(read_text(png) == single_png) << n << " chunks by " << split << ": denoised PNG differs";
  }
  const std::string plain = render_chunks(dir, "plain", 2, "samples");
  const auto r = run_sylva("merge" + plain + " -o " + q(dir / "plain.exr") + " --denoise --quiet", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("rendered without --features"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "plain.exr"));
}

TEST(CliChunks, ForeignMissingAndDuplicatedPartsAreNamed) {
  const fs::path dir = fresh_dir("cli_chunks_refuse");
  render_chunks(dir, "a", 3, "samples");
  const fs::path a0 = dir / "a.0.part", a1 = dir / "a.1.part", a2 = dir / "a.2.part";
  const fs::path out = dir / "out.exr";
  // Missing.
  auto r = run_sylva("merge " + q(a0) + " " + q(a2) + " -o " + q(out), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing chunks 1 of 3"), std::string::npos) << r.err;
  // Duplicated.
  fs::copy_file(a1, dir / "again.part");
  r = run_sylva("merge " + q(a0) + " " + q(a1) + " " + q(dir / "again.part") + " " + q(a2) + " -o " + q(out), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((dir / "again.part").string() + ": duplicated part: chunk 1/3"), std::string::npos) << r.err;
  // Foreign: another seed, and another band set.
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o " + q(dir / "seed.part") +
                          " --chunk 1/3 --seed 5" + kCommon,
                      dir)
                .exit_code,
            0);
  r = run_sylva("merge " + q(a0) + " " + q(dir / "seed.part") + " " + q(a2) + " -o " + q(out), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((dir / "seed.part").string() + ": foreign part"), std::string::npos) << r.err;
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o " + q(dir / "bands.part") +
                          " --chunk 1/3 --bands rgb" + kCommon,
                      dir)
                .exit_code,
            0);
  r = run_sylva("merge " + q(a0) + " " + q(dir / "bands.part") + " " + q(a2) + " -o " + q(out), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((dir / "bands.part").string() + ": foreign part"), std::string::npos) << r.err;
  // A finished EXR is not a part.
  ASSERT_EQ(
      run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o " + q(dir / "full.exr") + kCommon, dir)
          .exit_code,
      0);
  r = run_sylva("merge " + q(dir / "full.exr") + " -o " + q(out), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not a Sylva partial render"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  // Bad chunk arguments.
  r = run_sylva(
      "render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o " + q(dir / "x.part") + " --chunk 3/3" + kCommon,
      dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("0 <= i < N"), std::string::npos) << r.err;
  r = run_sylva(
      "render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o " + q(dir / "x.part") + " --chunk 0/8" + kCommon,
      dir);  // 8 chunks of 7 spp
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("every chunk needs a sample"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.part"));
}

TEST(CliChunks, PartialMergePreviewsAndSaysWhatIsMissing) {
  const fs::path dir = fresh_dir("cli_chunks_partial");
  render_chunks(dir, "t", 3, "tiles");
  const fs::path out = dir / "preview.exr";
  const auto r =
      run_sylva("merge " + q(dir / "t.0.part") + " " + q(dir / "t.2.part") + " -o " + q(out) + " --partial", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("partial merge: chunks 1 of 3 missing"), std::string::npos) << r.err;
  ASSERT_EQ(
      run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o " + q(dir / "single.exr") + kCommon, dir)
          .exit_code,
      0);
  const Image preview = read_exr(out), single = read_exr(dir / "single.exr");
  const int g = single.find_channel("G");
  // Rows of the present chunks are exact; the missing band (rows 6..12 of 20) is black.
  for (int x = 0; x < single.width; ++x) {
    EXPECT_EQ(preview.at(x, 0, g), single.at(x, 0, g));
    EXPECT_EQ(preview.at(x, 19, g), single.at(x, 19, g));
    EXPECT_EQ(preview.at(x, 9, g), 0.0f);
  }
}

// A tree swaying in the wind in front of the camera (low quality, so it builds fast).
void write_wind_scene(const fs::path& file) {
  std::ofstream f(file);
  f << "[render]\nwidth = 24\nheight = 32\nspp = 2\nbands = [\"rgb\"]\n"
       "[camera]\nposition = [0.0, -14.0, 5.0]\ntarget = [0.0, 0.0, 5.0]\nvfov = 50\n"
       "[sun]\nazimuth = 140\nelevation = 40\n"
       "[materials.bark]\ntype = \"diffuse\"\nreflectance = 0.3\n"
       "[materials.leaf]\ntype = \"leaf\"\nreflectance = 0.4\ntransmittance = 0.3\n"
       "[[trees]]\nspecies = \""
    << SYLVA_SOURCE_DIR
    << "/data/species/quaking_aspen.toml\"\nseed = 3\nbark = \"bark\"\nleaf = \"leaf\"\nquality = 0.3\n"
       "wind = [12.0, 6.0]\n";
}

TEST(CliFrames, OneExrPerFrameAtWindTimeAndResumable) {
  const fs::path dir = fresh_dir("cli_frames");
  write_wind_scene(dir / "wind.toml");
  const std::string frames = "render " + q(dir / "wind.toml") + " -o " + q(dir / "anim.exr") + " --quiet";
  auto r = run_sylva(frames + " --frames 3:5 --fps 2", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"anim.0003.exr", "anim.0004.exr", "anim.0005.exr"}) EXPECT_TRUE(fs::exists(dir / name));
  EXPECT_FALSE(fs::exists(dir / "anim.0002.exr"));
  EXPECT_FALSE(fs::exists(dir / "anim.0006.exr"));
  // The wind moves the tree: frames differ.
  EXPECT_NE(read_text(dir / "anim.0003.exr"), read_text(dir / "anim.0004.exr"));
  // Frame 4 at 2 fps is the scene at time 2 s: a still render with `time = 2.0` gives the same bytes
  // except for the scene hash (the file text differs), so compare the pixels.
  {
    std::ofstream f(dir / "wind.toml", std::ios::app);
    f << "time = 2.0\n";
  }
  ASSERT_EQ(run_sylva("render " + q(dir / "wind.toml") + " -o " + q(dir / "still.exr") + " --quiet", dir).exit_code, 0);
  const Image frame = read_exr(dir / "anim.0004.exr"), still = read_exr(dir / "still.exr");
  ASSERT_EQ(frame.pixels.size(), still.pixels.size());
  EXPECT_TRUE(frame.pixels == still.pixels);
  // Re-submitted: existing frames are skipped (their files untouched), missing ones rendered.
  write_wind_scene(dir / "wind.toml");
  fs::remove(dir / "anim.0004.exr");
  const auto before = fs::last_write_time(dir / "anim.0003.exr");
  const std::string frame5 = read_text(dir / "anim.0005.exr");
  r = run_sylva("render " + q(dir / "wind.toml") + " -o " + q(dir / "anim.exr") + " --frames 3:5 --fps 2", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("2 frame(s) already rendered, skipped"), std::string::npos) << r.err;
  EXPECT_EQ(fs::last_write_time(dir / "anim.0003.exr"), before);
  ASSERT_TRUE(fs::exists(dir / "anim.0004.exr"));
  EXPECT_EQ(read_exr(dir / "anim.0004.exr").pixels, frame.pixels);
  EXPECT_EQ(read_text(dir / "anim.0005.exr"), frame5);
  r = run_sylva(frames + " --frames 5:3", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--frames"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace sylva
