#pragma once

// OpenEXR through its own library (core/image.h declares write_exr, which lives beside it): the
// reader of a file's first part, scan-line or tiled, for open_image.

#include "core/image_reader.h"

#include <filesystem>
#include <memory>
#include <string_view>

namespace sylva {

// The name the header's `capDate` is read under (the one OpenImageIO, which wrote Sylva's files
// before, gives it).
inline constexpr std::string_view kDateTime = "DateTime";

// Opens an OpenEXR file whose header check_exr_header has passed; OpenEXR's errors become Errors
// naming the file.
std::unique_ptr<ImageReader> open_exr_reader(const std::filesystem::path& path);

}  // namespace sylva
