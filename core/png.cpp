#include "core/png.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image.h"

#include <fmt/format.h>
#include <png.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace sylva {
namespace {

constexpr size_t kErrorBytes = 256;

// libpng reports errors through a callback that must not return: it records the message and
// jumps back to the setjmp of the function that called libpng. Those functions (below) hold no
// object with a destructor, so the jump skips none.
void on_png_error(png_structp png, png_const_charp message) {
  std::snprintf(static_cast<char*>(png_get_error_ptr(png)), kErrorBytes, "%s", message);
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

bool write_png_file(std::FILE* file, int width, int height, png_bytepp rows, char* error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, error, on_png_error, on_png_warning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {  // setjmp alone in the condition, as C requires
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

// A PNG being read: the C state libpng works on, released however reading ends.
struct PngState {
  std::FILE* file = nullptr;
  png_structp png = nullptr;
  png_infop info = nullptr;
  char error[kErrorBytes] = "out of memory";

  PngState() = default;
  PngState(const PngState&) = delete;
  PngState& operator=(const PngState&) = delete;
  ~PngState() {
    if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    if (file) std::fclose(file);
  }
};

// The header, with the expansions of open_png_reader; the sizes after them.
bool read_png_header(PngState& s, png_uint_32* width, png_uint_32* height, int* channels, int* bit_depth) {
  s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, s.error, on_png_error, on_png_warning);
  if (!s.png) return false;
  s.info = png_create_info_struct(s.png);
  if (!s.info) return false;
  if (setjmp(png_jmpbuf(s.png))) return false;
  png_init_io(s.png, s.file);
  png_read_info(s.png, s.info);
  png_set_expand(s.png);
  if (png_get_bit_depth(s.png, s.info) == 16) png_set_swap(s.png);  // to the host's byte order (x86-64)
  png_set_interlace_handling(s.png);
  png_read_update_info(s.png, s.info);
  *width = png_get_image_width(s.png, s.info);
  *height = png_get_image_height(s.png, s.info);
  *channels = png_get_channels(s.png, s.info);
  *bit_depth = png_get_bit_depth(s.png, s.info);
  return true;
}

bool read_png_rows(PngState& s, png_bytepp rows) {
  if (setjmp(png_jmpbuf(s.png))) return false;
  png_read_image(s.png, rows);
  png_read_end(s.png, nullptr);
  return true;
}

// libpng's message, except its "Read Error" for a file that ends early.
std::string read_error(const PngState& s) {
  return std::strcmp(s.error, "Read Error") == 0 ? "the file ends early (truncated)" : s.error;
}

class PngReader final : public ImageReader {
 public:
  explicit PngReader(const std::filesystem::path& path) {
    state_.file = std::fopen(path.c_str(), "rb");
    if (!state_.file) throw Error(fmt::format("{}: cannot read image: {}", path.string(), std::strerror(errno)));
    png_uint_32 width = 0, height = 0;
    int channels = 0, bit_depth = 0;
    if (!read_png_header(state_, &width, &height, &channels, &bit_depth))
      throw Error(fmt::format("{}: cannot read image: {}", path.string(), read_error(state_)));
    if (width > static_cast<png_uint_32>(kMaxSide) || height > static_cast<png_uint_32>(kMaxSide))
      throw Error(fmt::format("{}: image of {}x{} pixels is outside the limit of 0 to {} pixels per side",
                              path.string(), width, height, kMaxSide));
    spec_.width = spec_.full_width = static_cast<int>(width);
    spec_.height = spec_.full_height = static_cast<int>(height);
    spec_.channels = channels;
    spec_.format = bit_depth == 16 ? SampleType::UInt16 : SampleType::UInt8;
    spec_.channel_formats.assign(static_cast<size_t>(channels), spec_.format);
    static const std::vector<std::vector<std::string>> kNames{{"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
    spec_.channel_names = kNames[static_cast<size_t>(std::clamp(channels, 1, 4) - 1)];
    spec_.channel_names.resize(static_cast<size_t>(channels));
  }

  const ImageFileSpec& spec() const override { return spec_; }

  bool read_channels(float* planes) override {
    const size_t width = static_cast<size_t>(spec_.width), height = static_cast<size_t>(spec_.height);
    const size_t nc = static_cast<size_t>(spec_.channels);
    const size_t sample = spec_.format == SampleType::UInt16 ? 2 : 1;
    std::vector<unsigned char> pixels(width * height * nc * sample);
    std::vector<png_bytep> rows(height);
    for (size_t y = 0; y < height; ++y) rows[y] = pixels.data() + y * width * nc * sample;
    if (!read_png_rows(state_, rows.data())) {
      error_ = read_error(state_);
      return false;
    }
    const size_t plane = width * height;
    for (size_t p = 0; p < plane; ++p)
      for (size_t c = 0; c < nc; ++c) {
        float v = 0;
        if (sample == 2) {
          uint16_t s = 0;
          std::memcpy(&s, pixels.data() + (p * nc + c) * 2, 2);
          v = static_cast<float>(s);
        } else {
          v = static_cast<float>(pixels[p * nc + c]);
        }
        planes[c * plane + p] = v;
      }
    return true;
  }

  std::string error() const override { return error_; }

 private:
  static constexpr int kMaxSide = 1 << 24;  // beyond any limit image.cpp checks afterwards
  PngState state_;
  ImageFileSpec spec_;
  std::string error_;
};

}  // namespace

bool is_png(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char signature[8] = {};
  in.read(reinterpret_cast<char*>(signature), sizeof signature);
  return in.gcount() == 8 && png_sig_cmp(signature, 0, 8) == 0;
}

std::unique_ptr<ImageReader> open_png_reader(const std::filesystem::path& path) {
  return std::make_unique<PngReader>(path);
}

void write_png_rgb8(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * 3)
    throw Error(path.string() + ": inconsistent PNG pixels");
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  for (int y = 0; y < height; ++y)
    rows[static_cast<size_t>(y)] = const_cast<png_bytep>(rgb.data() + static_cast<size_t>(y) * 3 * width);
  write_file_atomic_by_name(path, [&](const std::filesystem::path& tmp) {
    std::FILE* file = std::fopen(tmp.c_str(), "wb");
    if (!file) throw Error(fmt::format("{}: cannot write: {}", path.string(), std::strerror(errno)));
    char error[kErrorBytes] = "out of memory";
    const bool ok = write_png_file(file, width, height, rows.data(), error);
    // The file is flushed to disk when committed (write_file_atomic_by_name).
    const bool written = std::fflush(file) == 0 && !std::ferror(file);
    const int saved_errno = errno;
    const bool closed = std::fclose(file) == 0;
    if (!ok) throw Error(fmt::format("{}: cannot write: {}", path.string(), error));
    if (!written || !closed)
      throw Error(fmt::format("{}: cannot write: {}", path.string(), std::strerror(saved_errno)));
  });
}

}  // namespace sylva
