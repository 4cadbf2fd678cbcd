// The OpenImageIO module (libsylva_oiio.so): reads any image format OpenImageIO knows for
// core/image.cpp, which loads the module only when a file is not OpenEXR (core/image_reader.h).

#include "core/image_reader.h"

#include <OpenImageIO/imageio.h>

#include <memory>

namespace sylva {
namespace {

SampleType sample_type(const OIIO::TypeDesc& t) {
  switch (t.basetype) {
    case OIIO::TypeDesc::UINT8:
      return SampleType::UInt8;
    case OIIO::TypeDesc::UINT16:
      return SampleType::UInt16;
    case OIIO::TypeDesc::UINT32:
      return SampleType::UInt32;
    case OIIO::TypeDesc::HALF:
      return SampleType::Half;
    case OIIO::TypeDesc::FLOAT:
      return SampleType::Float;
    default:
      return SampleType::Other;
  }
}

class OiioReader final : public ImageReader {
 public:
  explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)) {
    const OIIO::ImageSpec& s = in_->spec();
    spec_.width = s.width;
    spec_.height = s.height;
    spec_.depth = s.depth;
    spec_.channels = s.nchannels;
    spec_.x = s.x;
    spec_.y = s.y;
    spec_.full_x = s.full_x;
    spec_.full_y = s.full_y;
    spec_.full_width = s.full_width;
    spec_.full_height = s.full_height;
    spec_.format = sample_type(s.format);
    for (int c = 0; c < s.nchannels; ++c) {
      spec_.channel_formats.push_back(sample_type(s.channelformat(c)));
      spec_.channel_names.push_back(c < static_cast<int>(s.channelnames.size()) ? s.channelnames[c] : "");
    }
    for (const OIIO::ParamValue& p : s.extra_attribs) {
      const std::string name = p.name().string();
      if (p.type() != OIIO::TypeString || name == "compression" || name.rfind("oiio:", 0) == 0) continue;
      spec_.string_attributes.emplace_back(name, p.get_string());
    }
  }

  const ImageFileSpec& spec() const override { return spec_; }

  bool read_channels(float* planes) override {
    const size_t n = static_cast<size_t>(spec_.width) * static_cast<size_t>(spec_.height);
    for (int c = 0; c < spec_.channels; ++c) {
      float* plane = planes + static_cast<size_t>(c) * n;
      // Integer samples are read in their own type, so no conversion rescales them.
      const auto read_native = [&](auto zero, OIIO::TypeDesc type) {
        std::vector<decltype(zero)> raw(n);
        const bool ok = in_->read_image(0, 0, c, c + 1, type, raw.data());
        for (size_t i = 0; i < n; ++i) plane[i] = static_cast<float>(raw[i]);
        return ok;
      };
      bool ok = false;
      switch (spec_.channel_formats[static_cast<size_t>(c)]) {
        case SampleType::UInt8:
          ok = read_native(uint8_t{0}, OIIO::TypeDesc::UINT8);
          break;
        case SampleType::UInt16:
          ok = read_native(uint16_t{0}, OIIO::TypeDesc::UINT16);
          break;
        case SampleType::UInt32:
          ok = read_native(uint32_t{0}, OIIO::TypeDesc::UINT32);
          break;
        default:
          ok = in_->read_image(0, 0, c, c + 1, OIIO::TypeDesc::FLOAT, plane);
      }
      if (!ok) return false;
    }
    return true;
  }

  std::string error() const override { return in_->geterror(); }

 private:
  std::unique_ptr<OIIO::ImageInput> in_;
  ImageFileSpec spec_;
};

}  // namespace
}  // namespace sylva

extern "C" __attribute__((visibility("default"))) sylva::ImageReader* sylva_open_image_reader(const char* path,
                                                                                              std::string* error) {
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
  if (!in) {
    *error = OIIO::geterror();
    return nullptr;
  }
  return new sylva::OiioReader(std::move(in));
}
