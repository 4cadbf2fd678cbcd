// Split renders through partial files (render/chunk.h): chunk i of N by samples and by tiles,
// saved, loaded and merged in any file order equals one render bit for bit; foreign, duplicated
// and missing parts are refused naming the file; a partial merge is a preview that says what is
// missing.

#include "core/error.h"
#include "render/chunk.h"
#include "render/renderer.h"
#include "tests/render/render_test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::film_bytes;
using test::small_forest_scene;
using test::test_settings;

// 21 spp and 24 rows split unevenly into 2, 3 and 7 chunks.
constexpr int kWidth = 36, kHeight = 24, kSpp = 21, kDepth = 8;

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sylva_chunk_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

class ChunkedRender : public ::testing::Test {
 protected:
  ChunkedRender()
      : scene_(small_forest_scene()),
        embree_(scene_),
        renderer_(scene_, embree_, test_settings(kWidth, kHeight, kSpp, kDepth)) {
    reference_ = renderer_.make_film();
    renderer_.render(reference_);
  }

  PartialHeader header(int index, int count, ChunkSplit split) const {
    PartialHeader h;
    h.key = "scene abc seed 1";
    h.chunk = {index, count, split};
    h.spp = kSpp;
    h.job = {{"scene", "/some/forest.toml"}, {"bands", "rgb,nir"}};
    return h;
  }

  // Renders every chunk of an N-way split to files in `dir`; returns them shuffled.
  std::vector<fs::path> render_parts(const fs::path& dir, int count, ChunkSplit split) {
    std::vector<fs::path> files;
    for (int i = 0; i < count; ++i) {
      const ChunkWork work = chunk_work({i, count, split}, kWidth, kHeight, kSpp);
      Film film = renderer_.make_film(work.region, work.samples.first);
      renderer_.render(film, work.region, work.samples);
      files.push_back(dir / ("part" + std::to_string(i)));
      save_partial(files.back(), header(i, count, split), film);
    }
    std::shuffle(files.begin(), files.end(), std::mt19937(static_cast<unsigned>(count)));
    return files;
  }

  Scene scene_;
  EmbreeScene embree_;
  Renderer renderer_;
  Film reference_;
};

TEST(Chunks, ParseAndWork) {
  EXPECT_EQ(parse_chunk("2/7", "tiles"), (ChunkSpec{2, 7, ChunkSplit::tiles}));
  EXPECT_EQ(parse_chunk("0/1", "samples"), (ChunkSpec{0, 1, ChunkSplit::samples}));
  for (const char* bad : {"7/7", "-1/3", "1", "a/3", "1/0", "1/3x", "/3", ""})
    EXPECT_THROW(parse_chunk(bad, "samples"), Error) << bad;
  EXPECT_THROW(parse_chunk("0/2", "pixels"), Error);
  // Samples: every pixel, disjoint consecutive index ranges covering [0, spp).
  uint32_t next = 0;
  for (int i = 0; i < 7; ++i) {
    const ChunkWork w = chunk_work({i, 7, ChunkSplit::samples}, 10, 5, 21);
    EXPECT_EQ(w.region, PixelRegion::whole(10, 5));
    EXPECT_EQ(w.samples.first, next);
    next = w.samples.end;
  }
  EXPECT_EQ(next, 21u);
  // Tiles: bands of rows covering the image, all samples.
  int row = 0;
  for (int i = 0; i < 3; ++i) {
    const ChunkWork w = chunk_work({i, 3, ChunkSplit::tiles}, 10, 5, 21);
    EXPECT_EQ(w.region.y0, row);
    EXPECT_EQ(w.samples, (SampleRange{0, 21}));
    row = w.region.y1;
  }
  EXPECT_EQ(row, 5);
  EXPECT_THROW(chunk_work({0, 22, ChunkSplit::samples}, 10, 5, 21), Error);
  EXPECT_THROW(chunk_work({0, 6, ChunkSplit::tiles}, 10, 5, 21), Error);
}

TEST_F(ChunkedRender, MergedPartsEqualOneRenderBitForBit) {
  const std::string expected = film_bytes(reference_);
  for (const ChunkSplit split : {ChunkSplit::samples, ChunkSplit::tiles})
    for (const int n : {1, 2, 3, 7}) {
      const fs::path dir = temp_dir("merge");
      const MergedParts merged = merge_partials(render_parts(dir, n, split), false);
      EXPECT_EQ(film_bytes(merged.film), expected) << n << " chunks by " << to_string(split);
      EXPECT_TRUE(merged.missing.empty());
      EXPECT_EQ(merged.header.job, header(0, n, split).job);
      EXPECT_EQ(merged.header.spp, kSpp);
      fs::remove_all(dir);
    }
}

TEST_F(ChunkedRender, HeaderIsReadableAndRoundTrips) {
  const fs::path dir = temp_dir("header");
  const std::vector<fs::path> files = render_parts(dir, 3, ChunkSplit::samples);
  for (const fs::path& f : files) {
    const Partial p = load_partial(f);
    EXPECT_EQ(p.header.key, "scene abc seed 1");
    EXPECT_EQ(p.header.job.at("scene"), "/some/forest.toml");
    EXPECT_EQ(p.film.first_sample(), sample_chunk({0, kSpp}, p.header.chunk.index, 3).first);
    // Self-describing: the header is plain text at the start of the file.
    std::ifstream in(f, std::ios::binary);
    std::string text(400, '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    EXPECT_NE(text.find("chunk=" + std::to_string(p.header.chunk.index) + "/3\nsplit=samples\nspp=21\n"),
              std::string::npos);
  }
  fs::remove_all(dir);
}

TEST_F(ChunkedRender, ForeignDuplicatedAndMissingPartsAreRefusedByName) {
  const fs::path dir = temp_dir("refuse");
  std::vector<fs::path> files = render_parts(dir, 3, ChunkSplit::tiles);
  std::sort(files.begin(), files.end());
  auto message = [](const std::vector<fs::path>& parts) {
    try {
      merge_partials(parts, false);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("merged");
  };
  // Missing.
  std::string m = message({files[0], files[2]});
  EXPECT_NE(m.find("missing chunks 1 of 3"), std::string::npos) << m;
  // Duplicated (a copy under another name).
  fs::copy_file(files[1], dir / "copy");
  m = message({files[0], files[1], dir / "copy", files[2]});
  EXPECT_NE(m.find((dir / "copy").string() + ": duplicated part: chunk 1/3 is also " + files[1].string()),
            std::string::npos)
      << m;
  // Foreign: another render (key), other spp, another split, other job options.
  auto foreign = [&](const std::string& name, PartialHeader h) {
    const ChunkWork work = chunk_work(h.chunk, kWidth, kHeight, h.spp);
    save_partial(dir / name, h, renderer_.make_film(work.region, work.samples.first));
    const std::string msg = message({files[0], dir / name, files[2]});
    EXPECT_NE(msg.find((dir / name).string() + ": foreign part"), std::string::npos) << name << ": " << msg;
  };
  PartialHeader h = header(1, 3, ChunkSplit::tiles);
  h.key = "scene abd seed 1";
  foreign("other_key", h);
  h = header(1, 3, ChunkSplit::tiles);
  h.spp = kSpp + 1;
  foreign("other_spp", h);
  foreign("other_split", header(1, 3, ChunkSplit::samples));
  foreign("other_count", header(1, 4, ChunkSplit::tiles));
  h = header(1, 3, ChunkSplit::tiles);
  h.job["bands"] = "rgb";
  foreign("other_job", h);
  // Not a partial file at all.
  reference_.save(dir / "checkpoint", "k");
  m = message({dir / "checkpoint"});
  EXPECT_NE(m.find("not a Sylva partial render"), std::string::npos) << m;
  fs::remove_all(dir);
}

TEST_F(ChunkedRender, PartialMergeIsAPreviewThatSaysWhatIsMissing) {
  const fs::path dir = temp_dir("partial");
  // Tiles: the present bands are exact, the missing band is empty.
  std::vector<fs::path> tiles = render_parts(dir, 3, ChunkSplit::tiles);
  std::sort(tiles.begin(), tiles.end());
  const MergedParts t = merge_partials({tiles[0], tiles[2]}, true);
  EXPECT_EQ(t.missing, std::vector<int>{1});
  const PixelRegion gap = row_chunk(PixelRegion::whole(kWidth, kHeight), 1, 3);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (gap.contains(x, y)) {
        EXPECT_EQ(t.film.count(x, y), 0u);
      } else {
        ASSERT_EQ(t.film.count(x, y), static_cast<uint32_t>(kSpp));
        EXPECT_EQ(t.film.mean(x, y, 0), reference_.mean(x, y, 0));
      }
    }
  // Samples: chunks merge in order up to the first missing one; later ones are reported unused.
  const fs::path sdir = temp_dir("partial_samples");
  std::vector<fs::path> samples = render_parts(sdir, 7, ChunkSplit::samples);
  std::sort(samples.begin(), samples.end());
  const MergedParts s = merge_partials({samples[0], samples[1], samples[3], samples[5]}, true);
  EXPECT_EQ(s.missing, (std::vector<int>{2, 4, 6}));
  EXPECT_EQ(s.unused, (std::vector<int>{3, 5}));
  EXPECT_EQ(s.film.count(0, 0), sample_chunk({0, kSpp}, 1, 7).end);
  EXPECT_THROW(merge_partials({samples[1]}, true), Error);  // nothing starts at sample 0
  fs::remove_all(dir);
  fs::remove_all(sdir);
}

TEST_F(ChunkedRender, AssemblerMergesChunksArrivingInAnyOrder) {
  for (const ChunkSplit split : {ChunkSplit::samples, ChunkSplit::tiles}) {
    const int n = 7;
    ChunkAssembler assembler(kWidth, kHeight, reference_.channels(), n);
    for (const int i : {5, 2, 0, 6, 1, 4, 3}) {
      EXPECT_FALSE(assembler.complete());
      const ChunkWork work = chunk_work({i, n, split}, kWidth, kHeight, kSpp);
      Film film = renderer_.make_film(work.region, work.samples.first);
      renderer_.render(film, work.region, work.samples);
      if (i == 2) {
        EXPECT_THROW(assembler.film(), Error);
      }
      assembler.add(i, std::move(film));
    }
    ASSERT_TRUE(assembler.complete());
    EXPECT_EQ(film_bytes(assembler.film()), film_bytes(reference_)) << to_string(split);
    EXPECT_THROW(assembler.add(3, renderer_.make_film()), Error);  // twice
    EXPECT_THROW(assembler.add(7, renderer_.make_film()), Error);  // out of range
  }
}

}  // namespace
}  // namespace sylva
