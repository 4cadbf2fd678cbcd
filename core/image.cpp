#include "core/image.h"

#include "core/atomic_file.h"
#include "core/color.h"
#include "core/error.h"
#include "core/exr_file.h"
#include "core/image_header.h"
#include "core/input_file.h"

#include "core/image_reader.h"
#include "core/png.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace sylva {
namespace {

// The OpenImageIO module's open function, loaded on first use: from beside the executable (a copied
// installation), beside the shared object holding this code (the installed Python module), else
// from where the build put it.
OpenImageReaderFn oiio_module(const std::filesystem::path& file) {
  static const std::pair<OpenImageReaderFn, std::string> module = [] {
    constexpr const char* kName = "libsylva_oiio.so";
    std::vector<std::filesystem::path> candidates;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) candidates.push_back(exe.parent_path() / kName);
    Dl_info self{};
    if (dladdr(reinterpret_cast<const void*>(&oiio_module), &self) != 0 && self.dli_fname != nullptr) {
      const std::filesystem::path beside = std::filesystem::path(self.dli_fname).parent_path() / kName;
      if (candidates.empty() || beside != candidates.front()) candidates.push_back(beside);
    }
    candidates.emplace_back(SYLVA_OIIO_MODULE);
    std::string tried;
    for (const std::filesystem::path& candidate : candidates) {
      if (!std::filesystem::exists(candidate, ec)) {
        tried += fmt::format("{}{} (missing)", tried.empty() ? "" : ", ", candidate.string());
        continue;
      }
      void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        tried += fmt::format("{}{} ({})", tried.empty() ? "" : ", ", candidate.string(), dlerror());
        continue;
      }
      if (void* fn = dlsym(handle, kOpenImageReaderSymbol))
        return std::pair{reinterpret_cast<OpenImageReaderFn>(fn), std::string()};
      tried += fmt::format("{}{} (no {})", tried.empty() ? "" : ", ", candidate.string(), kOpenImageReaderSymbol);
    }
    return std::pair{OpenImageReaderFn{nullptr}, tried};
  }();
  if (!module.first)
    throw Error(fmt::format("{}: reading an image that is not OpenEXR needs OpenImageIO's module, not found: {}",
                            file.string(), module.second));
  return module.first;
}

// Opens an image file for reading after the checks every reader shares (the file exists, is a
// regular file, and an EXR header is sane).
std::unique_ptr<ImageReader> open_image(const std::filesystem::path& path, std::string_view what) {
  if (!std::filesystem::exists(path)) throw Error(path.string() + ": no such file");
  require_regular_file(path, std::string(what));
  check_exr_header(path);
  if (is_exr(path)) return open_exr_reader(path);
  if (is_png(path)) return open_png_reader(path);
  std::string error;
  std::unique_ptr<ImageReader> in(oiio_module(path)(path.c_str(), &error));
  if (!in) throw Error(path.string() + ": cannot read image" + (error.empty() ? "" : ": " + one_line(error)));
  return in;
}

}  // namespace

std::string printable(std::string_view text) {
  std::string out;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f)
      out += fmt::format("\\x{:02x}", byte);
    else
      out += c;
  }
  return out;
}

int Image::find_channel(std::string_view name) const {
  for (size_t c = 0; c < channels.size(); ++c)
    if (channels[c] == name) return static_cast<int>(c);
  return -1;
}

void Image::add_channel(std::string name, PixelType type) {
  const size_t old_count = channels.size();
  const size_t pixel_count = static_cast<size_t>(width) * static_cast<size_t>(height);
  std::vector<float> grown(pixel_count * (old_count + 1), 0.0f);
  for (size_t p = 0; p < pixel_count && old_count > 0; ++p)
    std::copy_n(pixels.begin() + static_cast<std::ptrdiff_t>(p * old_count), old_count,
                grown.begin() + static_cast<std::ptrdiff_t>(p * (old_count + 1)));
  pixels = std::move(grown);
  channels.push_back(std::move(name));
  types.push_back(type);
}

std::string Image::attribute(std::string_view key) const {
  for (const auto& [k, v] : attributes)
    if (k == key) return v;
  return "";
}

void Image::set_attribute(std::string key, std::string value) {
  for (auto& [k, v] : attributes)
    if (k == key) {
      v = std::move(value);
      return;
    }
  attributes.emplace_back(std::move(key), std::move(value));
}

Image make_image(int width, int height, std::vector<std::string> channels, PixelType type) {
  Image image;
  image.width = width;
  image.height = height;
  image.types.assign(channels.size(), type);
  image.channels = std::move(channels);
  image.pixels.assign(static_cast<size_t>(width) * static_cast<size_t>(height) * image.channels.size(), 0.0f);
  return image;
}

std::string_view raster_type_name(RasterType type) {
  switch (type) {
    case RasterType::UInt8:
      return "8-bit unsigned integer";
    case RasterType::UInt16:
      return "16-bit unsigned integer";
    case RasterType::UInt32:
      return "32-bit unsigned integer";
    case RasterType::Half:
      return "16-bit float";
    case RasterType::Float:
      return "32-bit float";
    case RasterType::Other:
      break;
  }
  return "an unsupported sample type";
}

namespace {

size_t sample_bytes(SampleType t) {
  switch (t) {
    case SampleType::UInt8:
      return 1;
    case SampleType::UInt16:
    case SampleType::Half:
      return 2;
    default:
      return 4;
  }
}

// Every channel plane of the data window, after the header's sizes passed check_image_header.
std::vector<float> read_planes(const std::filesystem::path& path, ImageReader& in) {
  const ImageFileSpec& spec = in.spec();
  std::vector<float> planes(static_cast<size_t>(spec.channels) * static_cast<size_t>(spec.width) *
                            static_cast<size_t>(spec.height));
  if (!in.read_channels(planes.data())) throw Error(path.string() + ": cannot read pixels: " + one_line(in.error()));
  return planes;
}

}  // namespace

Raster read_raster(const std::filesystem::path& path) {
  const std::unique_ptr<ImageReader> in = open_image(path, "raster");
  const ImageFileSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1) throw Error(path.string() + ": not a 2D image");
  if (spec.channels != 1)
    throw Error(fmt::format("{}: a raster needs exactly one channel, this image has {}", path.string(), spec.channels));
  check_image_header(path, ImageHeaderSizes{spec.width, spec.height, spec.width, spec.height, 1,
                                            static_cast<uint64_t>(sample_bytes(spec.format))});
  Raster r;
  r.width = spec.width;
  r.height = spec.height;
  r.type = spec.format;
  r.values = read_planes(path, *in);
  return r;
}

Image read_exr(const std::filesystem::path& path) {
  const std::unique_ptr<ImageReader> in = open_image(path, "image");
  const ImageFileSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.channels <= 0 || spec.depth > 1)
    throw Error(path.string() + ": not a 2D image with channels");

  const bool windowed = spec.full_width > 0 && spec.full_height > 0;
  {
    uint64_t stored_pixel_bytes = 0;
    for (SampleType t : spec.channel_formats) stored_pixel_bytes += sample_bytes(t);
    check_image_header(
        path, ImageHeaderSizes{windowed ? spec.full_width : spec.width, windowed ? spec.full_height : spec.height,
                               spec.width, spec.height, spec.channels, stored_pixel_bytes});
  }

  // The image is the display window; a smaller or offset data window (cropped renders from other
  // tools) is placed inside it, the rest left 0.
  Image image;
  image.width = windowed ? spec.full_width : spec.width;
  image.height = windowed ? spec.full_height : spec.height;
  const int x0 = windowed ? spec.x - spec.full_x : 0, y0 = windowed ? spec.y - spec.full_y : 0;
  image.channels = spec.channel_names;
  // 32-bit unsigned channels are ids; 8/16-bit ones (PNG, TIFF) are normalised colour.
  std::vector<float> scale;
  for (SampleType t : spec.channel_formats) {
    image.types.push_back(t == SampleType::UInt32 ? PixelType::UInt
                          : t == SampleType::Half ? PixelType::Half
                                                  : PixelType::Float);
    scale.push_back(t == SampleType::UInt8 ? 1.0f / 255.0f : t == SampleType::UInt16 ? 1.0f / 65535.0f : 1.0f);
  }
  for (const auto& [name, value] : spec.string_attributes) {
    if (name == kDateTime && value.empty()) continue;  // written by earlier versions for determinism
    image.attributes.emplace_back(name, value);
  }

  const std::vector<float> planes = read_planes(path, *in);
  const size_t nc = image.channels.size();
  image.pixels.assign(static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * nc, 0.0f);
  const size_t plane_size = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  for (size_t c = 0; c < nc; ++c) {
    const float* plane = planes.data() + c * plane_size;
    for (int y = 0; y < spec.height; ++y)
      for (int x = 0; x < spec.width; ++x)
        if (x + x0 >= 0 && x + x0 < image.width && y + y0 >= 0 && y + y0 < image.height)
          image.at(x + x0, y + y0, static_cast<int>(c)) =
              scale[c] * plane[static_cast<size_t>(y) * static_cast<size_t>(spec.width) + static_cast<size_t>(x)];
  }
  return image;
}

std::vector<uint8_t> make_preview_rgb8(const Image& image, const PreviewOptions& options) {
  int src[3];
  for (int i = 0; i < 3; ++i) {
    src[i] = image.find_channel(options.channels[static_cast<size_t>(i)]);
    if (src[i] < 0) throw Error("no channel \"" + options.channels[static_cast<size_t>(i)] + "\" to preview");
  }
  const size_t pixel_count = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  const size_t nc = image.channels.size();
  const float scale = std::exp2(options.exposure_ev);
  std::vector<float> rgb(pixel_count * 3);
  for (size_t p = 0; p < pixel_count; ++p)
    for (size_t i = 0; i < 3; ++i) {
      const float v = image.pixels[p * nc + static_cast<size_t>(src[i])] * scale;
      rgb[p * 3 + i] = std::isfinite(v) ? v : 0.0f;
    }
  apply_display_transform(rgb.data(), pixel_count, options.view);
  std::vector<uint8_t> bytes(rgb.size());
  for (size_t i = 0; i < rgb.size(); ++i) {
    const float v = std::isfinite(rgb[i]) ? std::clamp(rgb[i], 0.0f, 1.0f) : 0.0f;
    bytes[i] = static_cast<uint8_t>(std::lround(v * 255.0f));
  }
  return bytes;
}

void write_png_preview(const std::filesystem::path& path, const Image& image, const PreviewOptions& options) {
  std::vector<uint8_t> bytes;
  try {
    bytes = make_preview_rgb8(image, options);
  } catch (const Error& e) {
    throw Error(path.string() + ": " + e.what());
  }
  write_png_rgb8(path, image.width, image.height, bytes);
}

void write_text_file(const std::filesystem::path& path, std::string_view text) {
  write_file_atomic(path,
                    [&](std::ostream& out) { out.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

}  // namespace sylva
