#include "core/image.h"

#include "core/atomic_file.h"
#include "core/color.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/memory.h"

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>

namespace sylva {
namespace {

// No codec OpenImageIO reads packs pixels much tighter than deflate's limit of about 1032:1.
constexpr uint64_t kMaxCompressionRatio = 2048;

OIIO::TypeDesc storage_type(PixelType type) {
  switch (type) {
    case PixelType::Float:
      return OIIO::TypeDesc::FLOAT;
    case PixelType::Half:
      return OIIO::TypeDesc::HALF;
    case PixelType::UInt:
      return OIIO::TypeDesc::UINT32;
  }
  return OIIO::TypeDesc::FLOAT;
}

std::string oiio_error(const std::string& what) {
  const std::string detail = OIIO::geterror();
  return detail.empty() ? what : what + ": " + detail;
}

// The sizes an image header claims, checked before anything is allocated from them: a corrupt or
// hostile header can claim any window (docs/limits.md).
struct ImageHeaderSizes {
  int64_t display_width, display_height;  // the display window (the image read_exr returns)
  int64_t data_width, data_height;        // the data window (the pixels stored)
  int64_t channels;
  uint64_t stored_pixel_bytes;  // bytes of one stored pixel, all channels, before compression
};

void check_image_header(const std::filesystem::path& path, const ImageHeaderSizes& h) {
  const auto side_ok = [](int64_t side) { return side >= 0 && side <= kMaxImageSide; };
  if (!side_ok(h.display_width) || !side_ok(h.display_height) || !side_ok(h.data_width) || !side_ok(h.data_height))
    throw Error(
        fmt::format("{}: image of {}x{} pixels (data window {}x{}) is outside the limit of 0 to {} pixels per side",
                    path.string(), h.display_width, h.display_height, h.data_width, h.data_height, kMaxImageSide));
  if (h.channels > kMaxImageChannels)
    throw Error(
        fmt::format("{}: {} channels is more than the limit of {}", path.string(), h.channels, kMaxImageChannels));
  const uint64_t data = static_cast<uint64_t>(h.data_width) * static_cast<uint64_t>(h.data_height);
  const uint64_t file_bytes = std::filesystem::file_size(path);
  if (data * h.stored_pixel_bytes > kMaxCompressionRatio * file_bytes + (uint64_t{1} << 16))
    throw Error(fmt::format("{}: header claims {}x{} pixels of {} channels, more than a file of {} bytes can hold",
                            path.string(), h.data_width, h.data_height, h.channels, file_bytes));
  const uint64_t display = static_cast<uint64_t>(h.display_width) * static_cast<uint64_t>(h.display_height);
  const uint64_t bytes = (display * static_cast<uint64_t>(h.channels) + 2 * data) * sizeof(float);
  const uint64_t available = available_memory_bytes();
  if (bytes > available)
    throw Error(fmt::format("{}: reading this {}-channel image needs {:.1f} GiB but only {:.1f} GiB are available",
                            path.string(), h.channels, static_cast<double>(bytes) / double(uint64_t{1} << 30),
                            static_cast<double>(available) / double(uint64_t{1} << 30)));
}

// The attributes every EXR header must have (OpenEXR file layout, "Header Attributes"), with their
// type and, where fixed, their size in bytes (-1: any); a tiled file (version flag 0x200) also needs
// `tiles`.
struct RequiredExrAttribute {
  std::string_view name, type;
  int64_t size;
};
constexpr std::array<RequiredExrAttribute, 9> kRequiredExrAttributes{{
    {"channels", "chlist", -1},
    {"compression", "compression", 1},
    {"dataWindow", "box2i", 16},
    {"displayWindow", "box2i", 16},
    {"lineOrder", "lineOrder", 1},
    {"pixelAspectRatio", "float", 4},
    {"screenWindowCenter", "v2f", 8},
    {"screenWindowWidth", "float", 4},
    {"tiles", "tiledesc", 9},
}};
constexpr uint32_t kExrTiledFlag = 0x200;

// OpenEXR allocates from its header's windows while opening a file (the line-offset table), before
// OpenImageIO reports a spec, and spends seconds and gigabytes on a header without a data window,
// so the header of an EXR is read and checked first. Walks the attributes of the first part
// (OpenEXR file layout: magic, version, then name\0 type\0 size value until an empty name): every
// required attribute must be there with its type and size, and dataWindow, displayWindow (box2i)
// and channels (chlist) must be within the limits. A file that ends inside its header is refused;
// a header longer than the 64 KiB read here is left to OpenEXR past that point.
void check_exr_header(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(size_t{1} << 16, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  if (head.size() < 8 || head.compare(0, 4, "\x76\x2f\x31\x01") != 0) return;
  const uint64_t file_bytes = std::filesystem::file_size(path);
  const bool whole_file = head.size() == file_bytes;
  const auto int32_at = [&](size_t at) {
    int32_t v = 0;
    std::memcpy(&v, head.data() + at, sizeof v);
    return static_cast<int64_t>(v);
  };
  const auto box_sides = [&](size_t at) {
    return std::pair{int32_at(at + 8) - int32_at(at) + 1, int32_at(at + 12) - int32_at(at + 4) + 1};
  };
  const auto truncated = [&] {
    return Error(fmt::format("{}: the file ends inside its EXR header (truncated)", path.string()));
  };
  std::pair<int64_t, int64_t> data{0, 0}, display{0, 0};
  int64_t channels = 0;
  uint64_t pixel_bytes = 0;
  std::array<bool, kRequiredExrAttributes.size()> present{};
  size_t at = 8;
  while (at < head.size() && head[at] != '\0') {
    const size_t name_end = head.find('\0', at);
    const size_t type_end = name_end == std::string::npos ? name_end : head.find('\0', name_end + 1);
    if (type_end == std::string::npos || type_end + 5 > head.size()) {
      if (whole_file) throw truncated();
      return;
    }
    const std::string name = head.substr(at, name_end - at);
    const std::string type = head.substr(name_end + 1, type_end - name_end - 1);
    const int64_t size = int32_at(type_end + 1);
    const size_t value = type_end + 5;
    if (size < 0 || value + static_cast<uint64_t>(size) > file_bytes)
      throw Error(fmt::format("{}: header attribute '{}' claims {} bytes, more than the file holds", path.string(),
                              name, size));
    if (value + static_cast<uint64_t>(size) > head.size()) return;
    for (size_t r = 0; r < kRequiredExrAttributes.size(); ++r) {
      const RequiredExrAttribute& required = kRequiredExrAttributes[r];
      if (name != required.name) continue;
      if (type != required.type || (required.size >= 0 && size != required.size))
        throw Error(fmt::format("{}: header attribute '{}' is a {} of {} bytes, expected a {}", path.string(), name,
                                type, size, required.type));
      present[r] = true;
    }
    if (name == "dataWindow") data = box_sides(value);
    if (name == "displayWindow") display = box_sides(value);
    if (name == "channels") {
      // name\0, pixel type (0 uint, 1 half, 2 float), pLinear, 3 reserved, x and y sampling.
      for (size_t c = value; c < value + static_cast<size_t>(size) && head[c] != '\0';) {
        const size_t channel_end = head.find('\0', c);
        if (channel_end == std::string::npos || channel_end + 17 > value + static_cast<size_t>(size)) break;
        ++channels;
        pixel_bytes += int32_at(channel_end + 1) == 1 ? 2 : 4;
        c = channel_end + 17;
      }
    }
    at = value + static_cast<size_t>(size);
  }
  if (at >= head.size()) {
    if (whole_file) throw truncated();
    return;
  }
  const bool tiled = (static_cast<uint32_t>(int32_at(4)) & kExrTiledFlag) != 0;
  std::string missing;
  for (size_t r = 0; r < kRequiredExrAttributes.size(); ++r) {
    const std::string_view name = kRequiredExrAttributes[r].name;
    if (!present[r] && (name != "tiles" || tiled)) missing += fmt::format("{}'{}'", missing.empty() ? "" : ", ", name);
  }
  if (!missing.empty())
    throw Error(fmt::format("{}: the EXR header lacks the required attribute(s) {}", path.string(), missing));
  check_image_header(path,
                     ImageHeaderSizes{display.first, display.second, data.first, data.second, channels, pixel_bytes});
}

}  // namespace

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

void write_exr(const std::filesystem::path& path, const Image& image) {
  const int nc = image.channel_count();
  if (image.width <= 0 || image.height <= 0 || nc == 0) throw Error(path.string() + ": cannot write an empty image");
  if (image.types.size() != image.channels.size() || image.pixels.size() != static_cast<size_t>(image.width) *
                                                                                static_cast<size_t>(image.height) *
                                                                                image.channels.size())
    throw Error(path.string() + ": inconsistent image (channels, types and pixels disagree)");

  OIIO::ImageSpec spec(image.width, image.height, nc, OIIO::TypeDesc::FLOAT);
  spec.channelnames = image.channels;
  spec.channelformats.clear();
  for (PixelType t : image.types) spec.channelformats.push_back(storage_type(t));
  spec.alpha_channel = image.find_channel("A");
  spec.z_channel = image.find_channel("Z");
  spec.attribute("compression", "zip");
  // OpenImageIO stamps the current time (EXR capDate) unless told otherwise; an empty DateTime
  // keeps files byte-identical for identical images, so renders can be checked by file hash.
  spec.attribute("DateTime", "");
  for (const auto& [key, value] : image.attributes) spec.attribute(key, value);
  if (image.find_channel("R") >= 0 && image.find_channel("G") >= 0 && image.find_channel("B") >= 0)
    spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), rec709_chromaticities.data());

  // Native per-channel layout: OIIO would treat integer formats as normalised if asked to convert
  // floats, so the pixels are packed here in each channel's own type.
  std::vector<size_t> offsets(static_cast<size_t>(nc));
  size_t pixel_bytes = 0;
  for (int c = 0; c < nc; ++c) {
    offsets[static_cast<size_t>(c)] = pixel_bytes;
    pixel_bytes += spec.channelformats[static_cast<size_t>(c)].size();
  }
  const size_t pixel_count = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  std::vector<unsigned char> packed(pixel_count * pixel_bytes);
  for (size_t p = 0; p < pixel_count; ++p)
    for (int c = 0; c < nc; ++c) {
      const float v = image.pixels[p * static_cast<size_t>(nc) + static_cast<size_t>(c)];
      unsigned char* dst = packed.data() + p * pixel_bytes + offsets[static_cast<size_t>(c)];
      switch (image.types[static_cast<size_t>(c)]) {
        case PixelType::Float:
          std::memcpy(dst, &v, sizeof v);
          break;
        case PixelType::Half: {
          const Imath::half h(v);
          std::memcpy(dst, &h, sizeof h);
          break;
        }
        case PixelType::UInt: {
          const uint32_t u = std::isfinite(v) && v > 0.0f ? static_cast<uint32_t>(std::lround(v)) : 0u;
          std::memcpy(dst, &u, sizeof u);
          break;
        }
      }
    }

  write_file_atomic_by_name(path, [&](const std::filesystem::path& tmp) {
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("openexr");
    if (!out) throw Error(path.string() + ": " + oiio_error("OpenImageIO has no OpenEXR writer"));
    if (!out->open(tmp.string(), spec)) throw Error(path.string() + ": cannot write: " + out->geterror());
    const bool ok = out->write_image(OIIO::TypeDesc::UNKNOWN, packed.data());
    const std::string write_error = ok ? "" : out->geterror();
    if (!out->close() || !ok) throw Error(path.string() + ": cannot write: " + (ok ? out->geterror() : write_error));
  });
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

Raster read_raster(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw Error(path.string() + ": no such file");
  require_regular_file(path, "raster");
  check_exr_header(path);
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path.string());
  if (!in) throw Error(path.string() + ": " + oiio_error("cannot read image"));
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1) throw Error(path.string() + ": not a 2D image");
  if (spec.nchannels != 1)
    throw Error(
        fmt::format("{}: a raster needs exactly one channel, this image has {}", path.string(), spec.nchannels));
  check_image_header(path, ImageHeaderSizes{spec.width, spec.height, spec.width, spec.height, 1,
                                            static_cast<uint64_t>(spec.format.size())});
  Raster r;
  r.width = spec.width;
  r.height = spec.height;
  switch (spec.format.basetype) {
    case OIIO::TypeDesc::UINT8:
      r.type = RasterType::UInt8;
      break;
    case OIIO::TypeDesc::UINT16:
      r.type = RasterType::UInt16;
      break;
    case OIIO::TypeDesc::UINT32:
      r.type = RasterType::UInt32;
      break;
    case OIIO::TypeDesc::HALF:
      r.type = RasterType::Half;
      break;
    case OIIO::TypeDesc::FLOAT:
      r.type = RasterType::Float;
      break;
    default:
      r.type = RasterType::Other;
  }
  const size_t n = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  r.values.resize(n);
  bool ok = false;
  // Integer samples are read in their own type, so no conversion rescales them.
  const auto read_native = [&](auto zero) {
    std::vector<decltype(zero)> raw(n);
    const bool read = in->read_image(0, 0, 0, 1, spec.format, raw.data());
    for (size_t i = 0; i < n; ++i) r.values[i] = static_cast<float>(raw[i]);
    return read;
  };
  if (r.type == RasterType::UInt8) {
    ok = read_native(uint8_t{0});
  } else if (r.type == RasterType::UInt16) {
    ok = read_native(uint16_t{0});
  } else if (r.type == RasterType::UInt32) {
    ok = read_native(uint32_t{0});
  } else {
    ok = in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, r.values.data());
  }
  if (!ok) throw Error(path.string() + ": cannot read pixels: " + in->geterror());
  return r;
}

Image read_exr(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw Error(path.string() + ": no such file");
  require_regular_file(path, "image");
  check_exr_header(path);
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path.string());
  if (!in) throw Error(path.string() + ": " + oiio_error("cannot read image"));
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1)
    throw Error(path.string() + ": not a 2D image with channels");

  const bool windowed = spec.full_width > 0 && spec.full_height > 0;
  {
    uint64_t stored_pixel_bytes = 0;
    for (int c = 0; c < spec.nchannels; ++c) stored_pixel_bytes += spec.channelformat(c).size();
    check_image_header(
        path, ImageHeaderSizes{windowed ? spec.full_width : spec.width, windowed ? spec.full_height : spec.height,
                               spec.width, spec.height, spec.nchannels, stored_pixel_bytes});
  }

  // The image is the display window; a smaller or offset data window (cropped renders from other
  // tools) is placed inside it, the rest left 0.
  Image image;
  image.width = windowed ? spec.full_width : spec.width;
  image.height = windowed ? spec.full_height : spec.height;
  const int x0 = windowed ? spec.x - spec.full_x : 0, y0 = windowed ? spec.y - spec.full_y : 0;
  image.channels = spec.channelnames;
  for (int c = 0; c < spec.nchannels; ++c) {
    // 32-bit unsigned channels are ids; 8/16-bit ones (PNG, TIFF) are normalised colour.
    const OIIO::TypeDesc f = spec.channelformat(c);
    image.types.push_back(f.basetype == OIIO::TypeDesc::UINT32 ? PixelType::UInt
                          : f.basetype == OIIO::TypeDesc::HALF ? PixelType::Half
                                                               : PixelType::Float);
  }
  for (const OIIO::ParamValue& p : spec.extra_attribs) {
    const std::string name = p.name().string();
    if (p.type() != OIIO::TypeString || name == "compression" || name.rfind("oiio:", 0) == 0) continue;
    const std::string value = p.get_string();
    if (name == "DateTime" && value.empty()) continue;  // written by write_exr for determinism
    image.attributes.emplace_back(name, value);
  }

  // Read each channel in its native type (32-bit ids must not be normalised).
  const size_t data_count = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  const size_t nc = image.channels.size();
  image.pixels.assign(static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * nc, 0.0f);
  std::vector<float> plane(data_count);
  std::vector<uint32_t> ids;
  for (size_t c = 0; c < nc; ++c) {
    const int ci = static_cast<int>(c);
    bool ok = false;
    if (image.types[c] == PixelType::UInt) {
      ids.resize(data_count);
      ok = in->read_image(0, 0, ci, ci + 1, OIIO::TypeDesc::UINT32, ids.data());
      for (size_t p = 0; p < data_count; ++p) plane[p] = static_cast<float>(ids[p]);
    } else {
      ok = in->read_image(0, 0, ci, ci + 1, OIIO::TypeDesc::FLOAT, plane.data());
    }
    if (!ok) throw Error(path.string() + ": cannot read channel " + image.channels[c] + ": " + in->geterror());
    for (int y = 0; y < spec.height; ++y)
      for (int x = 0; x < spec.width; ++x)
        if (x + x0 >= 0 && x + x0 < image.width && y + y0 >= 0 && y + y0 < image.height)
          image.at(x + x0, y + y0, ci) =
              plane[static_cast<size_t>(y) * static_cast<size_t>(spec.width) + static_cast<size_t>(x)];
  }
  return image;
}

void write_png_rgb8(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * 3)
    throw Error(path.string() + ": inconsistent PNG pixels");
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", "sRGB");
  write_file_atomic_by_name(path, [&](const std::filesystem::path& tmp) {
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("png");
    if (!out) throw Error(path.string() + ": " + oiio_error("OpenImageIO has no PNG writer"));
    if (!out->open(tmp.string(), spec)) throw Error(path.string() + ": cannot write: " + out->geterror());
    const bool ok = out->write_image(OIIO::TypeDesc::UINT8, rgb.data());
    const std::string write_error = ok ? "" : out->geterror();
    if (!out->close() || !ok) throw Error(path.string() + ": cannot write: " + (ok ? out->geterror() : write_error));
  });
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
