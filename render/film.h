#pragma once
// The film: per pixel, per channel sums and sums of squares of the sample values, and the number of
// samples taken, so the mean and the variance of the mean are known (for goldens, resume and, later,
// adaptive sampling). The channels are the renderer's: each band channel's radiance, then its albedo
// AOV (render/renderer.h); the first-hit AOVs (depth, normals, ids) are a function of the pixel
// centre alone and are traced when the image is made, so the film needs no other state for them.
//
// A film covers a window of the image (the whole image, or a region: a tile of a split render) and
// holds each of its pixels' samples from index first_sample() on.
//
// Summation order, and why merges are exact. Floating-point addition is not associative, so two
// films can only merge to the bits of a single render if every pixel's samples are added in one
// fixed order. Sylva's order is the simplest one: a pixel's sample values are added one at a time,
// in sample-index order, to running double sums that start at zero — what a single render, any
// number of threads and an interrupted-then-resumed render all do. Hence:
//   - Films of disjoint windows merge by copying pixels: trivially exact.
//   - A film that starts at sample 0 needs only its running sums.
//   - A film that starts later (a chunk [a, b) of a sample-split render) cannot know the sums of
//     samples 0..a-1 it must be added onto, so it also keeps every sample's values, in order, and
//     merge() replays them onto the film that ends at sample a: the same additions in the same
//     order as one render over [0, b), so the same bits. Chunks merge in sample order, in any
//     grouping ((A+B)+C or A+(B+C)).
// Rejected alternatives: fixed-size sample blocks whose partial sums are added in a fixed order
// change the bits of every render longer than one block (goldens, checkpoints), and a chunk must
// still keep each of its blocks' partial sums apart; exact (superaccumulator) sums make every order
// exact but cost about 7x the memory of every film. The price of the chosen order is paid only by
// sample chunks that do not start at 0: 4 bytes per channel per sample per pixel. Split large
// images by region (free) and use sample chunks for small images or few samples.

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace sylva {

// A rectangle of image pixels, [x0, x1) × [y0, y1), in raster coordinates (x right, y down,
// pixel (0, 0) top left).
struct PixelRegion {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  static PixelRegion whole(int width, int height) { return {0, 0, width, height}; }
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  size_t pixel_count() const { return empty() ? 0 : static_cast<size_t>(width()) * static_cast<size_t>(height()); }
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
  bool contains(const PixelRegion& r) const {
    return r.empty() || (r.x0 >= x0 && r.x1 <= x1 && r.y0 >= y0 && r.y1 <= y1);
  }
  bool operator==(const PixelRegion&) const = default;
};

// Sample indices [first, end) of every pixel.
struct SampleRange {
  uint32_t first = 0, end = 0;
  uint32_t size() const { return end > first ? end - first : 0; }
  bool operator==(const SampleRange&) const = default;
};

// Chunk `index` of `count` (0 <= index < count) of a split render: consecutive, disjoint, as equal
// as integers allow, covering the whole input in order. For `sylva render --chunk i/N` and MPI.
SampleRange sample_chunk(SampleRange samples, int index, int count);
PixelRegion row_chunk(const PixelRegion& region, int index, int count);  // bands of whole rows

class Film {
 public:
  Film() = default;
  // The whole width×height image, samples from index 0 on.
  Film(int width, int height, int channels);
  // The pixels of `window` (inside the width×height image), samples from `first_sample` on.
  Film(int width, int height, int channels, const PixelRegion& window, uint32_t first_sample);

  int width() const { return width_; }  // of the image, not of the window
  int height() const { return height_; }
  int channels() const { return channels_; }
  const PixelRegion& window() const { return window_; }
  uint32_t first_sample() const { return first_sample_; }
  // Whether the film keeps every sample's values for merge() (first_sample() > 0).
  bool keeps_samples() const { return first_sample_ > 0; }

  // Adds the next sample (index first_sample() + count(x, y)) of image pixel (x, y), inside window().
  void add_sample(int x, int y, const float* values) {
    const size_t p = pixel(x, y), base = p * static_cast<size_t>(channels_);
    for (int c = 0; c < channels_; ++c) {
      const double v = values[c];
      sum_[base + c] += v;
      sum_sq_[base + c] += v * v;
    }
    if (!samples_.empty()) samples_[p].insert(samples_[p].end(), values, values + channels_);
    ++count_[p];
  }
  uint32_t count(int x, int y) const { return count_[pixel(x, y)]; }
  double mean(int x, int y, int c) const;
  // The running sums of channel c's sample values and of their squares.
  double sum(int x, int y, int c) const { return sum_[pixel(x, y) * static_cast<size_t>(channels_) + c]; }
  double sum_sq(int x, int y, int c) const { return sum_sq_[pixel(x, y) * static_cast<size_t>(channels_) + c]; }
  // Variance of the pixel mean (sample variance / n); 0 with fewer than two samples.
  double variance_of_mean(int x, int y, int c) const;
  uint64_t total_samples() const;

  // Adds `other`'s samples to this film, bit-exactly (see the summation order above). Both films
  // must be of the same image and channels, and other's window inside this one. For every pixel
  // where `other` has samples, they must continue this pixel's: other.first_sample() ==
  // first_sample() + count(x, y). An empty pixel is copied; otherwise other's kept samples are
  // replayed in order. Throws sylva::Error on anything else (a gap or an overlap), leaving this
  // film unchanged.
  void merge(const Film& other);

  // Checkpoints: a binary file with a key (what was being rendered) that resume must match.
  // Written atomically. load throws sylva::Error on a mismatched key, size or a corrupt file.
  void save(const std::filesystem::path& file, const std::string& key) const;
  static Film load(const std::filesystem::path& file, const std::string& key);
  // The same format on a stream, for files that embed a film after a header of their own (the
  // partial files of render/chunk.h). read() expects the film to run to the end of the stream and
  // names `name` in its errors.
  void write(std::ostream& out, const std::string& key) const;
  static Film read(std::istream& in, const std::string& key, const std::string& name);

 private:
  size_t pixel(int x, int y) const {
    return static_cast<size_t>(y - window_.y0) * static_cast<size_t>(window_.width()) +
           static_cast<size_t>(x - window_.x0);
  }
  void copy_pixel(const Film& other, int x, int y);

  int width_ = 0, height_ = 0, channels_ = 0;
  PixelRegion window_;
  uint32_t first_sample_ = 0;
  std::vector<double> sum_, sum_sq_;
  std::vector<uint32_t> count_;
  // Per pixel, when keeps_samples(): every sample's channel values in sample order.
  std::vector<std::vector<float>> samples_;
};

}  // namespace sylva
