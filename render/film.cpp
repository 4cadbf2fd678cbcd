#include "render/film.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <cstring>
#include <fstream>

namespace sylva {

namespace {
// Version 1: the whole image from sample 0 (count, sum, sum_sq). Version 2 adds the window, the
// first sample and, when the film keeps them, every sample's values.
constexpr char kMagic1[8] = {'S', 'Y', 'L', 'V', 'A', 'C', 'K', '1'};
constexpr char kMagic2[8] = {'S', 'Y', 'L', 'V', 'A', 'C', 'K', '2'};

template <typename T>
void write_pod(std::ostream& out, const T& v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <typename T>
void read_pod(std::istream& in, T& v) {
  in.read(reinterpret_cast<char*>(&v), sizeof(T));
}
template <typename T>
void write_vec(std::ostream& out, const std::vector<T>& v) {
  out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
}
template <typename T>
void read_vec(std::istream& in, std::vector<T>& v) {
  in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
}
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
  out.write(kMagic2, sizeof(kMagic2));
  write_pod(out, static_cast<uint64_t>(key.size()));
  out.write(key.data(), static_cast<std::streamsize>(key.size()));
  for (const int v : {width_, height_, channels_, window_.x0, window_.y0, window_.x1, window_.y1})
    write_pod(out, static_cast<int32_t>(v));
  write_pod(out, first_sample_);
  write_vec(out, count_);
  write_vec(out, sum_);
  write_vec(out, sum_sq_);
  for (const std::vector<float>& values : samples_) write_vec(out, values);
}

Film Film::load(const std::filesystem::path& file, const std::string& key) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": no checkpoint to resume from");
  return read(in, key, file.string());
}

Film Film::read(std::istream& in, const std::string& key, const std::string& name) {
  char magic[sizeof(kMagic2)];
  in.read(magic, sizeof(magic));
  const bool v1 = in && std::memcmp(magic, kMagic1, sizeof(kMagic1)) == 0;
  if (!in || (!v1 && std::memcmp(magic, kMagic2, sizeof(kMagic2)) != 0)) throw Error(name + ": not a Sylva checkpoint");
  uint64_t key_size = 0;
  read_pod(in, key_size);
  if (!in || key_size > (1u << 20)) throw Error(name + ": corrupt checkpoint header");
  std::string stored(key_size, '\0');
  in.read(stored.data(), static_cast<std::streamsize>(key_size));
  if (stored != key)
    throw Error(name + ": checkpoint is of a different render (scene, seed, resolution, bands or depth differ)");
  int32_t w = 0, h = 0, c = 0;
  read_pod(in, w);
  read_pod(in, h);
  read_pod(in, c);
  PixelRegion window = PixelRegion::whole(w, h);
  uint32_t first = 0;
  if (!v1) {
    for (int* v : {&window.x0, &window.y0, &window.x1, &window.y1}) {
      int32_t i = 0;
      read_pod(in, i);
      *v = i;
    }
    read_pod(in, first);
  }
  if (!in || w <= 0 || h <= 0 || c <= 0 || w > 65536 || h > 65536 || c > 1024 || window.empty() ||
      !PixelRegion::whole(w, h).contains(window))
    throw Error(name + ": corrupt checkpoint header");
  Film film(w, h, c, window, first);
  read_vec(in, film.count_);
  read_vec(in, film.sum_);
  read_vec(in, film.sum_sq_);
  if (!in) throw Error(name + ": truncated checkpoint");
  if (film.keeps_samples()) {
    // The kept values must be exactly what the counts say the rest of the file holds.
    const auto here = in.tellg();
    in.seekg(0, std::ios::end);
    const uint64_t rest = static_cast<uint64_t>(in.tellg() - here);
    in.seekg(here);
    uint64_t expected = 0;
    for (const uint32_t n : film.count_)
      expected += static_cast<uint64_t>(n) * static_cast<uint64_t>(c) * sizeof(float);
    if (rest != expected) throw Error(name + ": corrupt checkpoint (kept samples do not match the counts)");
    for (size_t p = 0; p < film.samples_.size(); ++p) {
      film.samples_[p].resize(static_cast<size_t>(film.count_[p]) * static_cast<size_t>(c));
      read_vec(in, film.samples_[p]);
    }
    if (!in) throw Error(name + ": truncated checkpoint");
  }
  return film;
}

}  // namespace sylva
