#include "core/image.h"

#include "core/atomic_file.h"
#include "core/color.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/memory.h"

#include "core/image_reader.h"
#include "core/png.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <thread>

namespace sylva {
namespace {

// The first four bytes of every OpenEXR file.
constexpr char kExrMagic[] = "\x76\x2f\x31\x01";

// No codec packs pixels much tighter than deflate's limit of about 1032:1.
constexpr uint64_t kMaxCompressionRatio = 2048;

// The sizes an image header claims, checked before anything is allocated from them: a corrupt or
// hostile header can claim any window (docs/limits.md).
struct ImageHeaderSizes {
  int64_t display_width, display_height;  // the display window (the image read_exr returns)
  int64_t data_width, data_height;        // the data window (the pixels stored)
  int64_t channels;
  uint64_t stored_pixel_bytes;  // bytes of one stored pixel, all channels, before compression
};

// A reader's error as one line: OpenImageIO reports every error it recorded on a line of its own
// (its PNG reader gave libpng's message, then "PNG read error: ...", then "PNG library error"),
// joined here with "; "; OpenEXR's messages quote names from the file as they are.
std::string one_line(std::string_view text) {
  std::string line;
  for (size_t at = 0; at < text.size();) {
    const size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view part = text.substr(at, end - at);
    if (part.find_first_not_of(" \t\r") != std::string_view::npos) line += (line.empty() ? "" : "; ") + printable(part);
    at = end + 1;
  }
  return line;
}

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
  // The image, every channel's plane of the data window, and one plane of raw samples.
  const uint64_t channels = static_cast<uint64_t>(h.channels);
  const uint64_t bytes = (display * channels + data * (channels + 1)) * sizeof(float);
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

// The longest attribute or type name OpenEXR reads (with the long-names flag), and the longest
// channel list within kMaxImageChannels: per channel its name and NUL, pixel type, pLinear and 3
// reserved bytes, x and y sampling; then the list's closing NUL.
constexpr size_t kMaxExrName = 255;
constexpr int64_t kMaxExrChannelList = int64_t{kMaxImageChannels} * (kMaxExrName + 1 + 16) + 1;

// OpenEXR allocates from its header's windows while opening a file (the line-offset table), before
// OpenImageIO reports a spec, and spends seconds and gigabytes on a header without a data window,
// so the header of an EXR is read and checked first. Walks the attributes of the first part
// (OpenEXR file layout: magic, version, then name\0 type\0 size value until an empty name), all of
// them, reading only the values it checks and seeking past the others, so a header of any length
// (a 70 KB one hid a missing data window from a first 64 KiB read) costs little time and memory:
// every required attribute must be there with its type and size, and dataWindow, displayWindow
// (box2i) and channels (chlist) must be within the limits. A file that ends inside its header is
// refused.
void check_exr_header(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 8> start{};
  in.read(start.data(), start.size());
  if (in.gcount() < 8 || std::memcmp(start.data(), kExrMagic, 4) != 0) return;
  const uint64_t file_bytes = std::filesystem::file_size(path);
  const auto truncated = [&] {
    return Error(fmt::format("{}: the file ends inside its EXR header (truncated)", path.string()));
  };
  const auto read_name = [&](std::string& name) {
    name.clear();
    for (char c; in.get(c);) {
      if (c == '\0') return;
      if (name.size() == kMaxExrName)
        throw Error(fmt::format("{}: header name '{}...' is longer than {} bytes", path.string(),
                                printable(name.substr(0, 32)), kMaxExrName));
      name += c;
    }
    throw truncated();
  };
  const auto int32_at = [](const std::string& bytes, size_t at) {
    int32_t v = 0;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    return static_cast<int64_t>(v);
  };
  const auto box_sides = [&](const std::string& box) {
    return std::pair{int32_at(box, 8) - int32_at(box, 0) + 1, int32_at(box, 12) - int32_at(box, 4) + 1};
  };
  std::pair<int64_t, int64_t> data{0, 0}, display{0, 0};
  int64_t channels = 0;
  uint64_t pixel_bytes = 0;
  std::array<bool, kRequiredExrAttributes.size()> present{};
  std::string name, type, value;
  for (;;) {
    read_name(name);
    if (name.empty()) break;
    read_name(type);
    std::array<char, 4> size_bytes{};
    if (!in.read(size_bytes.data(), size_bytes.size())) throw truncated();
    int32_t size32 = 0;
    std::memcpy(&size32, size_bytes.data(), sizeof size32);
    const int64_t size = size32;
    const auto at = static_cast<uint64_t>(in.tellg());
    if (size < 0 || at + static_cast<uint64_t>(size) > file_bytes)
      throw Error(fmt::format("{}: header attribute '{}' claims {} bytes, more than the file holds", path.string(),
                              printable(name), size));
    for (size_t r = 0; r < kRequiredExrAttributes.size(); ++r) {
      const RequiredExrAttribute& required = kRequiredExrAttributes[r];
      if (name != required.name) continue;
      if (type != required.type || (required.size >= 0 && size != required.size))
        throw Error(fmt::format("{}: header attribute '{}' is a {} of {} bytes, expected a {}", path.string(), name,
                                printable(type), size, required.type));
      present[r] = true;
    }
    if (name != "dataWindow" && name != "displayWindow" && name != "channels") {
      in.seekg(size, std::ios::cur);
      continue;
    }
    if (size > kMaxExrChannelList)
      throw Error(fmt::format("{}: a channel list of {} bytes names more than the limit of {} channels", path.string(),
                              size, kMaxImageChannels));
    value.resize(static_cast<size_t>(size));
    if (!in.read(value.data(), size)) throw truncated();
    if (name == "dataWindow") data = box_sides(value);
    if (name == "displayWindow") display = box_sides(value);
    if (name == "channels") {
      // name\0, pixel type (0 uint, 1 half, 2 float), pLinear, 3 reserved, x and y sampling.
      for (size_t c = 0; c < value.size() && value[c] != '\0';) {
        const size_t channel_end = value.find('\0', c);
        if (channel_end == std::string::npos || channel_end + 17 > value.size()) break;
        ++channels;
        pixel_bytes += int32_at(value, channel_end + 1) == 1 ? 2 : 4;
        c = channel_end + 17;
      }
    }
  }
  uint32_t version = 0;  // the format version in its low byte, then flags
  std::memcpy(&version, start.data() + 4, sizeof version);
  const bool tiled = (version & kExrTiledFlag) != 0;
  std::string missing;
  for (size_t r = 0; r < kRequiredExrAttributes.size(); ++r) {
    const std::string_view required = kRequiredExrAttributes[r].name;
    if (!present[r] && (required != "tiles" || tiled))
      missing += fmt::format("{}'{}'", missing.empty() ? "" : ", ", required);
  }
  if (!missing.empty())
    throw Error(fmt::format("{}: the EXR header lacks the required attribute(s) {}", path.string(), missing));
  check_image_header(path,
                     ImageHeaderSizes{display.first, display.second, data.first, data.second, channels, pixel_bytes});
}

// OpenEXR compresses and decompresses blocks of scan lines on its own thread pool; the bytes do not
// depend on the number of threads.
void use_exr_threads() {
  static std::once_flag once;
  std::call_once(
      once, [] { Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency()))); });
}

SampleType sample_type(Imf::PixelType t) {
  switch (t) {
    case Imf::UINT:
      return SampleType::UInt32;
    case Imf::HALF:
      return SampleType::Half;
    case Imf::FLOAT:
      return SampleType::Float;
    default:
      return SampleType::Other;
  }
}

Imf::PixelType exr_type(PixelType t) {
  switch (t) {
    case PixelType::Half:
      return Imf::HALF;
    case PixelType::UInt:
      return Imf::UINT;
    case PixelType::Float:
      break;
  }
  return Imf::FLOAT;
}

// The EXR header's `capDate` is the image's "DateTime" (the name OpenImageIO, which wrote Sylva's
// files before, gives it).
constexpr std::string_view kDateTime = "DateTime";
constexpr std::string_view kExrDateTime = "capDate";

// Channels in reading order: by layer (the name up to its last dot; unlayered first), within a
// layer R, G, B, A first, then by name — the order OpenImageIO gave, which reports and tests show.
std::vector<int> reading_order(const std::vector<std::string>& names) {
  const auto key = [&](int i) {
    const std::string& n = names[static_cast<size_t>(i)];
    const size_t dot = n.rfind('.');
    const std::string layer = dot == std::string::npos ? "" : n.substr(0, dot + 1);
    const std::string suffix = dot == std::string::npos ? n : n.substr(dot + 1);
    constexpr std::array<std::string_view, 4> first{"R", "G", "B", "A"};
    const auto at = std::find(first.begin(), first.end(), suffix);
    return std::tuple(layer, at - first.begin(), suffix);
  };
  std::vector<int> order(names.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  return order;
}

// A scan-line or tiled OpenEXR file (its first part), read with OpenEXR's own library.
class ExrReader final : public ImageReader {
 public:
  explicit ExrReader(const std::filesystem::path& path) : file_(path.c_str()) {
    const Imf::Header& h = file_.header();
    const Imath::Box2i data = h.dataWindow(), display = h.displayWindow();
    spec_.x = data.min.x;
    spec_.y = data.min.y;
    spec_.width = data.max.x - data.min.x + 1;
    spec_.height = data.max.y - data.min.y + 1;
    spec_.full_x = display.min.x;
    spec_.full_y = display.min.y;
    spec_.full_width = display.max.x - display.min.x + 1;
    spec_.full_height = display.max.y - display.min.y + 1;
    std::vector<std::string> names;
    std::vector<Imf::Channel> channels;
    for (auto c = h.channels().begin(); c != h.channels().end(); ++c) {
      if (c.channel().xSampling != 1 || c.channel().ySampling != 1)
        throw Error(
            fmt::format("{}: channel {} is subsampled, which Sylva does not read", path.string(), printable(c.name())));
      names.emplace_back(c.name());
      channels.push_back(c.channel());
    }
    for (int i : reading_order(names)) {
      spec_.channel_names.push_back(names[static_cast<size_t>(i)]);
      spec_.channel_formats.push_back(sample_type(channels[static_cast<size_t>(i)].type));
    }
    spec_.channels = static_cast<int>(spec_.channel_names.size());
    spec_.format = spec_.channel_formats.empty() ? SampleType::Other : spec_.channel_formats.front();
    for (auto a = h.begin(); a != h.end(); ++a)
      if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&a.attribute()))
        spec_.string_attributes.emplace_back(a.name() == kExrDateTime ? kDateTime : a.name(), text->value());
  }

  const ImageFileSpec& spec() const override { return spec_; }

  bool read_channels(float* planes) override {
    const Imath::Box2i window = file_.header().dataWindow();
    const size_t plane = static_cast<size_t>(spec_.width) * static_cast<size_t>(spec_.height);
    Imf::FrameBuffer frame;
    // OpenEXR converts half and unsigned samples to float by value.
    for (size_t c = 0; c < spec_.channel_names.size(); ++c)
      frame.insert(spec_.channel_names[c], Imf::Slice::Make(Imf::FLOAT, planes + c * plane, window));
    try {
      file_.setFrameBuffer(frame);
      file_.readPixels(window.min.y, window.max.y);
    } catch (const std::exception& e) {
      error_ = e.what();
      return false;
    }
    return true;
  }

  std::string error() const override { return error_; }

 private:
  Imf::InputFile file_;
  ImageFileSpec spec_;
  std::string error_;
};

// The OpenImageIO module's open function, loaded on first use: from beside the executable (a copied
// installation), else from where the build put it.
OpenImageReaderFn oiio_module(const std::filesystem::path& file) {
  static const std::pair<OpenImageReaderFn, std::string> module = [] {
    constexpr const char* kName = "libsylva_oiio.so";
    std::vector<std::filesystem::path> candidates;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) candidates.push_back(exe.parent_path() / kName);
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

bool is_exr(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  in.read(magic, sizeof magic);
  return in.gcount() == 4 && std::memcmp(magic, kExrMagic, 4) == 0;
}

// Opens an image file for reading after the checks every reader shares (the file exists, is a
// regular file, and an EXR header is sane).
std::unique_ptr<ImageReader> open_image(const std::filesystem::path& path, std::string_view what) {
  if (!std::filesystem::exists(path)) throw Error(path.string() + ": no such file");
  require_regular_file(path, std::string(what));
  check_exr_header(path);
  if (is_exr(path)) {
    use_exr_threads();
    try {
      return std::make_unique<ExrReader>(path);
    } catch (const Error&) {
      throw;
    } catch (const std::exception& e) {
      throw Error(fmt::format("{}: cannot read image: {}", path.string(), one_line(e.what())));
    }
  }
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

void write_exr(const std::filesystem::path& path, const Image& image) {
  const int nc = image.channel_count();
  if (image.width <= 0 || image.height <= 0 || nc == 0) throw Error(path.string() + ": cannot write an empty image");
  if (image.types.size() != image.channels.size() || image.pixels.size() != static_cast<size_t>(image.width) *
                                                                                static_cast<size_t>(image.height) *
                                                                                image.channels.size())
    throw Error(path.string() + ": inconsistent image (channels, types and pixels disagree)");

  // No capture date unless the image has one, so identical images give identical files.
  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  try {
    for (int c = 0; c < nc; ++c)
      header.channels().insert(image.channels[static_cast<size_t>(c)],
                               Imf::Channel(exr_type(image.types[static_cast<size_t>(c)])));
    for (const auto& [key, value] : image.attributes) {
      if (key == kDateTime && value.empty()) continue;
      header.insert(key == kDateTime ? std::string(kExrDateTime) : key, Imf::StringAttribute(value));
    }
    // An image read from another tool's file may bring a text attribute of this name (a `sylva
    // compare --report` copies its inputs' attributes); it is kept as it came, since OpenEXR refuses
    // to give one name two types.
    if (image.find_channel("R") >= 0 && image.find_channel("G") >= 0 && image.find_channel("B") >= 0 &&
        header.find("chromaticities") == header.end()) {
      const auto& xy = rec709_chromaticities;
      Imf::addChromaticities(header, Imf::Chromaticities(Imath::V2f(xy[0], xy[1]), Imath::V2f(xy[2], xy[3]),
                                                         Imath::V2f(xy[4], xy[5]), Imath::V2f(xy[6], xy[7])));
    }
  } catch (const std::exception& e) {
    throw Error(fmt::format("{}: cannot write the header: {}", path.string(), e.what()));
  }

  // Each channel in its own type, pixel after pixel.
  std::vector<size_t> offsets(static_cast<size_t>(nc));
  size_t pixel_bytes = 0;
  for (int c = 0; c < nc; ++c) {
    offsets[static_cast<size_t>(c)] = pixel_bytes;
    pixel_bytes += image.types[static_cast<size_t>(c)] == PixelType::Half ? sizeof(Imath::half) : sizeof(float);
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
  Imf::FrameBuffer frame;
  for (int c = 0; c < nc; ++c)
    frame.insert(image.channels[static_cast<size_t>(c)],
                 Imf::Slice(exr_type(image.types[static_cast<size_t>(c)]),
                            reinterpret_cast<char*>(packed.data() + offsets[static_cast<size_t>(c)]), pixel_bytes,
                            pixel_bytes * static_cast<size_t>(image.width)));

  use_exr_threads();
  write_file_atomic_by_name(path, [&](const std::filesystem::path& tmp) {
    try {
      Imf::OutputFile out(tmp.c_str(), header);
      out.setFrameBuffer(frame);
      out.writePixels(image.height);
    } catch (const std::exception& e) {
      throw Error(path.string() + ": cannot write: " + e.what());
    }
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
