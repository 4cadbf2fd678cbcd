#include "render/film.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

namespace sylva {

namespace {
// Version 1: the whole image from sample 0 (count, sum, sum_sq). Version 2 adds the window, the
// first sample and, when the film keeps them, every sample's values. Version 3 (written since) is
// version 2 followed by a checksum: the WordHash64 (core/hash.h) of every field after the magic,
// each field (a value or an array) added as one piece, in file order. Versions 1 and 2 are still
// read, without a checksum.
constexpr char kMagic1[8] = {'S', 'Y', 'L', 'V', 'A', 'C', 'K', '1'};
constexpr char kMagic2[8] = {'S', 'Y', 'L', 'V', 'A', 'C', 'K', '2'};
constexpr char kMagic3[8] = {'S', 'Y', 'L', 'V', 'A', 'C', 'K', '3'};

// The most samples a pixel of a valid film can hold (the --spp limit).
constexpr uint32_t kMaxPixelSamples = 1u << 24;

// Writes fields, hashing each.
class FieldWriter {
 public:
  explicit FieldWriter(std::ostream& out) : out_(out) {}
  template <typename T>
  void pod(const T& v) {
    bytes(&v, sizeof(T));
  }
  template <typename T>
  void vec(const std::vector<T>& v) {
    bytes(v.data(), v.size() * sizeof(T));
  }
  void bytes(const void* data, size_t n) {
    out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
    hash_.add(data, n);
  }
  uint64_t checksum() const { return hash_.value(); }

 private:
  std::ostream& out_;
  WordHash64 hash_;
};

// Reads fields, hashing each.
class FieldReader {
 public:
  explicit FieldReader(std::istream& in) : in_(in) {}
  template <typename T>
  void pod(T& v) {
    bytes(&v, sizeof(T));
  }
  template <typename T>
  void vec(std::vector<T>& v) {
    bytes(v.data(), v.size() * sizeof(T));
  }
  void bytes(void* data, size_t n) {
    in_.read(static_cast<char*>(data), static_cast<std::streamsize>(n));
    hash_.add(data, n);
  }
  uint64_t checksum() const { return hash_.value(); }

 private:
  std::istream& in_;
  WordHash64 hash_;
};

}  // namespace

SampleRange sample_chunk(SampleRange samples, int index, int count) {
  if (count < 1 || index < 0 || index >= count) throw Error(fmt::format("chunk {}/{} does not exist", index, count));
  const uint64_t n = samples.size();
  return {samples.first + static_cast<uint32_t>(n * static_cast<uint64_t>(index) / static_cast<uint64_t>(count)),
          samples.first + static_cast<uint32_t>(n * static_cast<uint64_t>(index + 1) / static_cast<uint64_t>(count))};
}

PixelRegion row_chunk(const PixelRegion& region, int index, int count) {
  if (count < 1 || index < 0 || index >= count) throw Error(fmt::format("chunk {}/{} does not exist", index, count));
  const int64_t rows = std::max(0, region.height());
  return {region.x0, region.y0 + static_cast<int>(rows * index / count), region.x1,
          region.y0 + static_cast<int>(rows * (index + 1) / count)};
}

Film::Film(int width, int height, int channels) : Film(width, height, channels, PixelRegion::whole(width, height), 0) {}

Film::Film(int width, int height, int channels, const PixelRegion& window, uint32_t first_sample)
    : width_(width), height_(height), channels_(channels), window_(window), first_sample_(first_sample) {
  if (width <= 0 || height <= 0 || channels <= 0) throw Error("a film needs a positive size and channel count");
  if (window.empty() || !PixelRegion::whole(width, height).contains(window))
    throw Error(fmt::format("film window [{}, {}) x [{}, {}) is empty or outside the {}x{} image", window.x0, window.x1,
                            window.y0, window.y1, width, height));
  const size_t pixels = window.pixel_count();
  sum_.assign(pixels * static_cast<size_t>(channels), 0.0);
  sum_sq_.assign(pixels * static_cast<size_t>(channels), 0.0);
  count_.assign(pixels, 0u);
  if (first_sample > 0) samples_.resize(pixels);
}

double Film::mean(int x, int y, int c) const {
  const size_t p = pixel(x, y);
  return count_[p] ? sum_[p * channels_ + c] / count_[p] : 0.0;
}

double Film::variance_of_mean(int x, int y, int c) const {
  const size_t p = pixel(x, y);
  const double n = count_[p];
  if (n < 2) return 0.0;
  const double s = sum_[p * channels_ + c], s2 = sum_sq_[p * channels_ + c];
  return std::max(0.0, (s2 - s * s / n) / (n - 1)) / n;
}

uint64_t Film::total_samples() const {
  uint64_t t = 0;
  for (uint32_t c : count_) t += c;
  return t;
}

void Film::copy_pixel(const Film& other, int x, int y) {
  const size_t p = pixel(x, y), q = other.pixel(x, y), nc = static_cast<size_t>(channels_);
  std::copy_n(other.sum_.begin() + static_cast<std::ptrdiff_t>(q * nc), nc,
              sum_.begin() + static_cast<std::ptrdiff_t>(p * nc));
  std::copy_n(other.sum_sq_.begin() + static_cast<std::ptrdiff_t>(q * nc), nc,
              sum_sq_.begin() + static_cast<std::ptrdiff_t>(p * nc));
  count_[p] = other.count_[q];
  if (!samples_.empty()) samples_[p] = other.samples_[q];
}

void Film::merge(const Film& other) {
  if (other.width_ != width_ || other.height_ != height_ || other.channels_ != channels_)
    throw Error(fmt::format("cannot merge a {}x{} film of {} channels into a {}x{} film of {}", other.width_,
                            other.height_, other.channels_, width_, height_, channels_));
  const PixelRegion& w = other.window_;
  if (!window_.contains(w)) throw Error("cannot merge a film whose window is outside this film's window");
  // Check every pixel first, so a refused merge changes nothing.
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const uint32_t theirs = other.count(x, y), ours = count(x, y);
      if (theirs > 0 && other.first_sample_ != first_sample_ + ours)
        throw Error(
            fmt::format("cannot merge: pixel ({}, {}) has samples [{}, {}) here and [{}, {}) in the other "
                        "film; sample chunks merge in order, without gaps or overlaps",
                        x, y, first_sample_, first_sample_ + ours, other.first_sample_, other.first_sample_ + theirs));
    }
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const uint32_t theirs = other.count(x, y);
      if (theirs == 0) continue;
      if (count(x, y) == 0) {
        copy_pixel(other, x, y);
        continue;
      }
      // other.first_sample_ > first_sample_ >= 0 here, so `other` kept its samples.
      const std::vector<float>& values = other.samples_[other.pixel(x, y)];
      for (uint32_t s = 0; s < theirs; ++s) add_sample(x, y, values.data() + static_cast<size_t>(s) * channels_);
    }
}

void Film::save(const std::filesystem::path& file, const std::string& key) const {
  write_file_atomic(file, [&](std::ostream& out) { write(out, key); });
}

void Film::write(std::ostream& out, const std::string& key) const {
  out.write(kMagic3, sizeof(kMagic3));
  FieldWriter w(out);
  w.pod(static_cast<uint64_t>(key.size()));
  w.bytes(key.data(), key.size());
  for (const int v : {width_, height_, channels_, window_.x0, window_.y0, window_.x1, window_.y1})
    w.pod(static_cast<int32_t>(v));
  w.pod(first_sample_);
  w.vec(count_);
  w.vec(sum_);
  w.vec(sum_sq_);
  for (const std::vector<float>& values : samples_) w.vec(values);
  const uint64_t checksum = w.checksum();
  out.write(reinterpret_cast<const char*>(&checksum), sizeof(checksum));
}

Film Film::load(const std::filesystem::path& file, const std::string& key) {
  if (!std::filesystem::exists(file)) throw Error(file.string() + ": no checkpoint to resume from");
  require_regular_file(file, "checkpoint");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": no checkpoint to resume from");
  return read(in, key, file.string());
}

Film Film::read(std::istream& in, const std::string& key, const std::string& name) {
  char magic[sizeof(kMagic2)];
  in.read(magic, sizeof(magic));
  const bool v1 = in && std::memcmp(magic, kMagic1, sizeof(kMagic1)) == 0;
  const bool v3 = in && std::memcmp(magic, kMagic3, sizeof(kMagic3)) == 0;
  if (!in || (!v1 && !v3 && std::memcmp(magic, kMagic2, sizeof(kMagic2)) != 0))
    throw Error(name + ": not a Sylva checkpoint");
  FieldReader r(in);
  uint64_t key_size = 0;
  r.pod(key_size);
  if (!in || key_size > (1u << 20)) throw Error(name + ": corrupt checkpoint header");
  std::string stored(key_size, '\0');
  r.bytes(stored.data(), key_size);
  if (stored != key)
    throw Error(name + ": checkpoint is of a different render (scene, seed, resolution, bands or depth differ)");
  int32_t w = 0, h = 0, c = 0;
  r.pod(w);
  r.pod(h);
  r.pod(c);
  PixelRegion window = PixelRegion::whole(w, h);
  uint32_t first = 0;
  if (!v1) {
    for (int* v : {&window.x0, &window.y0, &window.x1, &window.y1}) {
      int32_t i = 0;
      r.pod(i);
      *v = i;
    }
    r.pod(first);
  }
  if (!in || w <= 0 || h <= 0 || c <= 0 || w > 65536 || h > 65536 || c > 1024 || window.empty() ||
      !PixelRegion::whole(w, h).contains(window))
    throw Error(name + ": corrupt checkpoint header");
  // The arrays must be in the stream before they are allocated (a corrupt header cannot ask for
  // gigabytes): count, sum and sum_sq, then the checksum.
  const auto here = in.tellg();
  in.seekg(0, std::ios::end);
  const uint64_t rest = static_cast<uint64_t>(in.tellg() - here);
  in.seekg(here);
  const uint64_t checksum_bytes = v3 ? sizeof(uint64_t) : 0;
  const uint64_t pixels = static_cast<uint64_t>(window.width()) * static_cast<uint64_t>(window.height());
  const uint64_t arrays = pixels * (sizeof(uint32_t) + 2 * static_cast<uint64_t>(c) * sizeof(double));
  if (!in || rest < arrays + checksum_bytes) throw Error(name + ": truncated checkpoint");
  Film film(w, h, c, window, first);
  r.vec(film.count_);
  r.vec(film.sum_);
  r.vec(film.sum_sq_);
  if (!in) throw Error(name + ": truncated checkpoint");
  if (film.keeps_samples()) {
    // The kept values must be exactly what the counts say the rest of the file holds.
    const auto after_arrays = in.tellg();
    in.seekg(0, std::ios::end);
    const uint64_t left = static_cast<uint64_t>(in.tellg() - after_arrays);
    in.seekg(after_arrays);
    if (left < checksum_bytes) throw Error(name + ": truncated checkpoint");
    const uint64_t kept_bytes = left - checksum_bytes;
    uint64_t expected = 0;
    for (const uint32_t n : film.count_)
      expected += static_cast<uint64_t>(n) * static_cast<uint64_t>(c) * sizeof(float);
    if (kept_bytes != expected) throw Error(name + ": corrupt checkpoint (kept samples do not match the counts)");
    for (size_t p = 0; p < film.samples_.size(); ++p) {
      film.samples_[p].resize(static_cast<size_t>(film.count_[p]) * static_cast<size_t>(c));
      r.vec(film.samples_[p]);
    }
    if (!in) throw Error(name + ": truncated checkpoint");
  }
  if (v3) {
    uint64_t stored_checksum = 0;
    in.read(reinterpret_cast<char*>(&stored_checksum), sizeof(stored_checksum));
    if (!in || stored_checksum != r.checksum())
      throw Error(name + ": corrupt checkpoint (checksum mismatch); it cannot be resumed: delete it and render again");
    if (in.peek() != std::char_traits<char>::eof())
      throw Error(name + ": corrupt checkpoint (data after the checksum)");
  }
  // Fields a valid film cannot hold, in files of any version.
  for (const uint32_t n : film.count_)
    if (n > kMaxPixelSamples)
      throw Error(
          fmt::format("{}: corrupt checkpoint (a pixel claims {} samples, more than {})", name, n, kMaxPixelSamples));
  for (size_t i = 0; i < film.sum_.size(); ++i)
    if (!std::isfinite(film.sum_[i]) || !(film.sum_sq_[i] >= 0.0) || !std::isfinite(film.sum_sq_[i]))
      throw Error(name + ": corrupt checkpoint (a pixel sum is not a finite number)");
  return film;
}

}  // namespace sylva
