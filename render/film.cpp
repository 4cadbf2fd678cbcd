#include "render/film.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <cstring>
#include <fstream>

namespace sylva {

namespace {
constexpr char kMagic[8] = {'S', 'Y', 'L', 'V', 'A', 'C', 'K', '1'};

template <typename T>
void write_pod(std::ostream& out, const T& v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <typename T>
void read_pod(std::ifstream& in, T& v) {
  in.read(reinterpret_cast<char*>(&v), sizeof(T));
}
template <typename T>
void write_vec(std::ostream& out, const std::vector<T>& v) {
  out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
}
template <typename T>
void read_vec(std::ifstream& in, std::vector<T>& v) {
  in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
}
}  // namespace

Film::Film(int width, int height, int channels)
    : width_(width),
      height_(height),
      channels_(channels),
      sum_(static_cast<size_t>(width) * height * channels, 0.0),
      sum_sq_(static_cast<size_t>(width) * height * channels, 0.0),
      count_(static_cast<size_t>(width) * height, 0u) {}

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

void Film::save(const std::filesystem::path& file, const std::string& key) const {
  write_file_atomic(file, [&](std::ostream& out) {
    out.write(kMagic, sizeof(kMagic));
    write_pod(out, static_cast<uint64_t>(key.size()));
    out.write(key.data(), static_cast<std::streamsize>(key.size()));
    write_pod(out, static_cast<int32_t>(width_));
    write_pod(out, static_cast<int32_t>(height_));
    write_pod(out, static_cast<int32_t>(channels_));
    write_vec(out, count_);
    write_vec(out, sum_);
    write_vec(out, sum_sq_);
  });
}

Film Film::load(const std::filesystem::path& file, const std::string& key) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": no checkpoint to resume from");
  char magic[sizeof(kMagic)];
  in.read(magic, sizeof(magic));
  if (!in || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) throw Error(file.string() + ": not a Sylva checkpoint");
  uint64_t key_size = 0;
  read_pod(in, key_size);
  if (!in || key_size > (1u << 20)) throw Error(file.string() + ": corrupt checkpoint header");
  std::string stored(key_size, '\0');
  in.read(stored.data(), static_cast<std::streamsize>(key_size));
  if (stored != key)
    throw Error(file.string() +
                ": checkpoint is of a different render (scene, seed, resolution, bands or depth differ)");
  int32_t w = 0, h = 0, c = 0;
  read_pod(in, w);
  read_pod(in, h);
  read_pod(in, c);
  if (!in || w <= 0 || h <= 0 || c <= 0 || w > 65536 || h > 65536 || c > 1024)
    throw Error(file.string() + ": corrupt checkpoint header");
  Film film(w, h, c);
  read_vec(in, film.count_);
  read_vec(in, film.sum_);
  read_vec(in, film.sum_sq_);
  if (!in) throw Error(file.string() + ": truncated checkpoint");
  return film;
}

}  // namespace sylva
