#include "core/exr_file.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image.h"
#include "core/image_header.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <mutex>
#include <thread>
#include <tuple>

namespace sylva {
namespace {

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

// The EXR header's `capDate` is the image's kDateTime.
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

}  // namespace

std::unique_ptr<ImageReader> open_exr_reader(const std::filesystem::path& path) {
  use_exr_threads();
  try {
    return std::make_unique<ExrReader>(path);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(fmt::format("{}: cannot read image: {}", path.string(), one_line(e.what())));
  }
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

}  // namespace sylva
