#pragma once

// Checks on an image file's header before anything is allocated from what it claims (docs/limits.md):
// the sizes every reader's header gives, and an OpenEXR header walked attribute by attribute.
// Shared by core's image readers (core/image.cpp, core/exr_file.cpp); not part of the API.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace sylva {

// The sizes an image header claims, checked before anything is allocated from them: a corrupt or
// hostile header can claim any window (docs/limits.md).
struct ImageHeaderSizes {
  int64_t display_width, display_height;  // the display window (the image read_exr returns)
  int64_t data_width, data_height;        // the data window (the pixels stored)
  int64_t channels;
  uint64_t stored_pixel_bytes;  // bytes of one stored pixel, all channels, before compression
};

// Refuses a header whose sides, channel count or pixel bytes are beyond the limits, more than the
// file can hold compressed, or more than the memory still available.
void check_image_header(const std::filesystem::path& path, const ImageHeaderSizes& h);

// Walks the first part's header of an OpenEXR file and refuses it when a required attribute is
// missing or malformed, its windows or channel list are beyond the limits, or it ends inside the
// header. Files that do not start with OpenEXR's magic number are left alone.
void check_exr_header(const std::filesystem::path& path);

// Whether the file starts with OpenEXR's magic number.
bool is_exr(const std::filesystem::path& path);

// A reader's error as one line: OpenImageIO reports every error it recorded on a line of its own
// (its PNG reader gave libpng's message, then "PNG read error: ...", then "PNG library error"),
// joined here with "; "; OpenEXR's messages quote names from the file as they are.
std::string one_line(std::string_view text);

}  // namespace sylva
