#pragma once
// The film: per pixel, per channel sums and sums of squares of the sample values, and the number of
// samples taken, so the mean and the variance of the mean are known (for goldens, resume and, later,
// adaptive sampling). Accumulation is in double, in sample order per pixel, so a render split into
// any number of sessions or threads sums to the same bits.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

class Film {
 public:
  Film() = default;
  Film(int width, int height, int channels);

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }

  void add_sample(int x, int y, const float* values) {
    const size_t p = pixel(x, y), base = p * static_cast<size_t>(channels_);
    for (int c = 0; c < channels_; ++c) {
      const double v = values[c];
      sum_[base + c] += v;
      sum_sq_[base + c] += v * v;
    }
    ++count_[p];
  }
  uint32_t count(int x, int y) const { return count_[pixel(x, y)]; }
  double mean(int x, int y, int c) const;
  // Variance of the pixel mean (sample variance / n); 0 with fewer than two samples.
  double variance_of_mean(int x, int y, int c) const;
  uint64_t total_samples() const;

  // Checkpoints: a binary file with a key (what was being rendered) that resume must match.
  // Written atomically. load throws sylva::Error on a mismatched key, size or a corrupt file.
  void save(const std::filesystem::path& file, const std::string& key) const;
  static Film load(const std::filesystem::path& file, const std::string& key);

 private:
  size_t pixel(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x);
  }

  int width_ = 0, height_ = 0, channels_ = 0;
  std::vector<double> sum_, sum_sq_;
  std::vector<uint32_t> count_;
};

}  // namespace sylva
