#pragma once
// Multi-channel images and their files: OpenEXR in and out (OpenEXR's library), other formats in
// (PNG through libpng, the rest through OpenImageIO's module: core/image_reader.h), and an 8-bit
// sRGB PNG preview through an OpenColorIO display transform (core/color.h).
//
// Channel names follow the EXR layer convention: "R","G","B","A", "nir.Y", "Z", "N.X", "albedo.R",
// "id.instance", and "var.<C>" for the variance of the pixel mean of channel C (image_compare.h).
// Files are written atomically (core/atomic_file.h): on failure <path> is left untouched and a
// sylva::Error naming it is thrown.

#include "core/image_reader.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sylva {

// Storage type of a channel in the EXR file. In memory every channel is a float.
enum class PixelType : uint8_t { Float, Half, UInt };

// A multi-channel image: pixels interleaved, index ((y*width + x)*channel_count + c), top row
// first. UInt channels (IDs) are held as exact floats (ids < 2^24) and written as 32-bit unsigned
// in EXR.
struct Image {
  int width = 0, height = 0;
  std::vector<std::string> channels;  // EXR names
  std::vector<PixelType> types;       // per channel (same size as channels)
  std::vector<float> pixels;
  std::vector<std::pair<std::string, std::string>> attributes;  // extra string header attributes

  int channel_count() const { return static_cast<int>(channels.size()); }
  int find_channel(std::string_view name) const;  // -1 if absent
  float& at(int x, int y, int c) { return pixels[index(x, y, c)]; }
  float at(int x, int y, int c) const { return pixels[index(x, y, c)]; }
  // Appends a channel, re-interleaving the existing pixels; the new channel is filled with 0.
  void add_channel(std::string name, PixelType type);
  std::string attribute(std::string_view key) const;  // "" if absent
  // Sets (replacing) a string attribute.
  void set_attribute(std::string key, std::string value);

 private:
  size_t index(int x, int y, int c) const {
    return (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * channels.size() +
           static_cast<size_t>(c);
  }
};

// A zero-filled image with every channel of one type.
Image make_image(int width, int height, std::vector<std::string> channels, PixelType type = PixelType::Float);

// The "chromaticities" written with R,G,B: linear Rec.709 / sRGB primaries, D65 white
// (x,y of red, green, blue, white).
inline constexpr std::array<float, 8> rec709_chromaticities{0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

// Writes OpenEXR (ZIP compression) with per-channel storage types, the string attributes, and the
// Rec.709 chromaticities when R, G and B are present. Deterministic: the same image gives the same
// bytes (no timestamp unless a "DateTime" attribute is given). Atomic; throws sylva::Error("path:
// why").
void write_exr(const std::filesystem::path& path, const Image& image);

// The largest image side Sylva renders or reads (docs/limits.md).
inline constexpr int kMaxImageSide = 65536;
// Text from an image file (a channel or attribute name), for a one-line message: a corrupt file's
// names hold any byte, so control bytes (line breaks among them) are shown as \xNN.
std::string printable(std::string_view text);

// The most channels an image read by read_exr may have.
inline constexpr int kMaxImageChannels = 1024;

// Reads the first part of an EXR (any file OpenImageIO reads) as its display window (a cropped data
// window is placed inside it, the rest 0). 32-bit unsigned channels become PixelType::UInt (exact),
// HALF ones Half, everything else Float (8/16-bit files normalised to [0, 1]). Channel order is the
// file's as OpenImageIO reports it (OpenEXR stores channels sorted by name; look channels up with
// find_channel). String header attributes are returned except OpenImageIO's own ("compression",
// "oiio:*"). Throws sylva::Error("path: why") on missing or corrupt files, and before allocating on
// headers beyond the limits: a side (display or data window) over kMaxImageSide, more than
// kMaxImageChannels channels, or pixels that would not fit in the memory still available.
Image read_exr(const std::filesystem::path& path);

// A single-channel raster as stored (elevation maps, feature maps): integer samples keep their
// integer values (a 16-bit PNG's 65535 reads as 65535.0, not 1.0), floats are read as they are.
// Its sample types are those an image file's header gives (core/image_reader.h).
using RasterType = SampleType;
struct Raster {
  int width = 0, height = 0;
  RasterType type = RasterType::Other;
  std::vector<float> values;  // values[y·width + x], top row first
};
std::string_view raster_type_name(RasterType type);  // "8-bit unsigned", "16-bit unsigned", ...
// Reads any image with exactly one channel (PNG, EXR, or another format OpenImageIO reads). Throws
// sylva::Error("path: why") for missing, unreadable or multi-channel files.
Raster read_raster(const std::filesystem::path& path);

struct PreviewOptions {
  float exposure_ev = 0.0f;       // scale linear values by 2^exposure_ev before the view transform
  std::string view = "Standard";  // a view of the shipped config's "sRGB" display (color.h)
  // Linear Rec.709 scene-referred input; the same name 3x gives a grey band (e.g. "nir.Y").
  std::array<std::string, 3> channels{"R", "G", "B"};
};

// The preview's pixels: 8-bit display code values, width*height*3, top row first. Non-finite
// values show as black. Throws sylva::Error naming a missing channel or an unknown view.
std::vector<uint8_t> make_preview_rgb8(const Image& image, const PreviewOptions& options);

// 8-bit sRGB PNG through an OCIO display transform of data/ocio/config.ocio. Atomic like write_exr.
void write_png_preview(const std::filesystem::path& path, const Image& image, const PreviewOptions& options);

// Writes a text file (e.g. an HTML report) atomically like write_exr.
void write_text_file(const std::filesystem::path& path, std::string_view text);

// Writes 8-bit RGB pixels (width*height*3, top row first) as a PNG. Atomic like write_exr.
void write_png_rgb8(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace sylva
