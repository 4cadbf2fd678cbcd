#pragma once
// Split renders: chunk i of N of a render's work, the partial file a chunk writes, and the merge of
// partial files back into the film of the whole render — bit-identical to a single-process render,
// because the films merge in the one summation order of render/film.h.
//
// Two ways to split (ChunkSplit):
//   - samples: every pixel, sample indices sample_chunk({0, spp}, i, N). Chunks after the first keep
//     every sample's values so the merge can replay them in order: 4 bytes per channel per sample
//     per pixel on disk and in memory. Best for small images with many samples.
//   - tiles: all spp samples of the rows row_chunk(image, i, N). Free to merge (pixels are copied).
//
// A partial file is self-describing: a text header (`head -c 2000 part` shows it) of `name=value`
// lines — the render's checkpoint key (render/session.h: Sylva's version, scene hash, seed,
// resolution, depth, bands), the chunk, the split, spp and whatever the caller needs to rebuild the
// render (the CLI stores the scene path and its overrides) — then the chunk's film in the
// checkpoint format (Film::write).

#include "render/film.h"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace sylva {

enum class ChunkSplit { samples, tiles };

struct ChunkSpec {
  int index = 0;  // 0 <= index < count
  int count = 1;
  ChunkSplit split = ChunkSplit::samples;
  bool operator==(const ChunkSpec&) const = default;
};

// "i/N" (0 <= i < N) and "samples" or "tiles"; throws sylva::Error naming the bad value.
ChunkSpec parse_chunk(const std::string& chunk, const std::string& split);
std::string to_string(ChunkSplit split);

// The pixels and sample indices chunk `spec` renders of a width×height image at spp samples.
// Throws sylva::Error when the split leaves a chunk without work (N > spp for samples, N > height
// for tiles).
struct ChunkWork {
  PixelRegion region;
  SampleRange samples;
};
ChunkWork chunk_work(const ChunkSpec& spec, int width, int height, int spp);

struct PartialHeader {
  std::string key;  // checkpoint_key() of the render
  ChunkSpec chunk;
  int spp = 0;
  // The caller's description of the render (e.g. "scene", "bands"): parts merge only if equal.
  // Names are [a-z0-9_]+; values are one line.
  std::map<std::string, std::string> job;
};

struct Partial {
  std::filesystem::path file;
  PartialHeader header;
  Film film;
};

// Written atomically. Throws sylva::Error if a job name or value cannot be stored.
void save_partial(const std::filesystem::path& file, const PartialHeader& header, const Film& film);
// Throws sylva::Error naming `file` if it is not a partial file or is corrupt.
Partial load_partial(const std::filesystem::path& file);
// Only the header (fast: the film is not read).
PartialHeader load_partial_header(const std::filesystem::path& file);

struct MergedParts {
  PartialHeader header;      // the parts' common header (chunk: index 0 of their N and split)
  Film film;                 // the whole image
  std::vector<int> missing;  // chunk indices not given (only with allow_missing)
  std::vector<int> unused;   // sample chunks given but not merged: after a missing one
};

// Assembles the films of all `count` chunks of a split render as they arrive, in any order (e.g.
// from MPI ranks): each is merged as soon as every chunk before it has been, so sample chunks
// merge in sample order and the result is bit-identical to one render.
class ChunkAssembler {
 public:
  ChunkAssembler(int width, int height, int channels, int count);
  // Throws sylva::Error for an index out of range or given twice, or a film of another image.
  void add(int index, Film film);
  bool complete() const { return next_ == count_; }
  // The whole image's film; throws sylva::Error unless complete().
  const Film& film() const;

 private:
  int count_ = 0, next_ = 0;
  Film film_;
  std::map<int, Film> waiting_;  // chunks that arrived before one they follow
  std::vector<bool> seen_;
};

// Merges the partial files of one render. Every part must have the same key, spp, chunk count,
// split and job as the first (else: "foreign part", naming both files), no chunk index may come
// twice ("duplicated", naming both files) and, unless allow_missing, every index must be there
// ("missing chunks", listing them). With allow_missing the merge is a preview: missing tiles stay
// empty (zero samples), and sample chunks merge in order up to the first missing one — the rest
// cannot be added onto a film with a gap in its sample indices and are listed in `unused`.
// Loads one part at a time.
MergedParts merge_partials(const std::vector<std::filesystem::path>& files, bool allow_missing);

}  // namespace sylva
