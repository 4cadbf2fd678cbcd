#pragma once

// Reading an image file: its header, then its channels. core/image.cpp reads OpenEXR with
// OpenEXR's library and PNG with libpng (core/png.h), and every other format (TIFF rasters, JPEG,
// ... given to `sylva compare`) through OpenImageIO in a module, libsylva_oiio.so
// (core/oiio/reader.cpp), loaded on first use:
// linking OpenImageIO pulls in some 250 shared libraries — a quarter of a second and 120 MB at
// every start of `sylva` — that a render, which writes EXR and PNG, never needs.
//
// Header-only on purpose: the module links OpenImageIO and none of Sylva's code, so nothing but
// these virtual functions crosses the boundary, and no exception does (same compiler and standard
// library on both sides: the module is built with the executable).

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sylva {

enum class SampleType : uint8_t { UInt8, UInt16, UInt32, Half, Float, Other };

// What a file's header says.
struct ImageFileSpec {
  int width = 0, height = 0, depth = 1, channels = 0;                  // data window size
  int x = 0, y = 0;                                                    // data window origin
  int full_x = 0, full_y = 0;                                          // display window origin
  int full_width = 0, full_height = 0;                                 // display window size (0: none)
  SampleType format = SampleType::Other;                               // the first channel's sample type
  std::vector<SampleType> channel_formats;                             // per channel
  std::vector<std::string> channel_names;                              // per channel
  std::vector<std::pair<std::string, std::string>> string_attributes;  // the header's text fields
};

class ImageReader {
 public:
  virtual ~ImageReader() = default;
  virtual const ImageFileSpec& spec() const = 0;
  // Every channel of the data window, channel after channel: `planes` holds channels·width·height
  // floats, each plane top row first. Samples are converted by value: an integer sample keeps its
  // integer value (no normalisation). False on a read error; then error() says what.
  virtual bool read_channels(float* planes) = 0;
  virtual std::string error() const = 0;
};

// The module's one exported function: opens `path`, or returns null and sets *error.
using OpenImageReaderFn = ImageReader* (*)(const char* path, std::string* error);
inline constexpr const char* kOpenImageReaderSymbol = "sylva_open_image_reader";

}  // namespace sylva
