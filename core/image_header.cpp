#include "core/image_header.h"

#include "core/error.h"
#include "core/image.h"
#include "core/memory.h"

#include <fmt/format.h>

#include <array>
#include <cstring>
#include <fstream>

namespace sylva {
namespace {

// The first four bytes of every OpenEXR file.
constexpr char kExrMagic[] = "\x76\x2f\x31\x01";

// No codec packs pixels much tighter than deflate's limit of about 1032:1.
constexpr uint64_t kMaxCompressionRatio = 2048;

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

}  // namespace

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

bool is_exr(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  in.read(magic, sizeof magic);
  return in.gcount() == 4 && std::memcmp(magic, kExrMagic, 4) == 0;
}

}  // namespace sylva
