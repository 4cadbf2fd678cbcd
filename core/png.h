#pragma once

// PNG files through libpng (core/image.cpp's reading, and the previews of write_png_rgb8): PNG rasters and PNG images
// given to `sylva compare` are read without OpenImageIO's module (core/image_reader.h).

#include "core/image_reader.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

namespace sylva {

// Whether the file starts with PNG's signature.
bool is_png(const std::filesystem::path& path);

// Opens a PNG and reads its header: palettes and bit depths below 8 are expanded to 8-bit samples,
// a tRNS chunk to an alpha channel; 16-bit samples stay 16-bit; no gamma is applied. Channels: Y,
// (Y, A), (R, G, B) or (R, G, B, A). Throws sylva::Error (`file: ...`) when the header is unreadable.
std::unique_ptr<ImageReader> open_png_reader(const std::filesystem::path& path);

// Writing: write_png_rgb8 (core/image.h), defined in core/png.cpp.

}  // namespace sylva
