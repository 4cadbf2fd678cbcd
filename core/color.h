#pragma once
// Colour management for previews: OpenColorIO display transforms from Sylva's shipped config
// (data/ocio/config.ocio, described in data/ocio/README.md). Scene-referred input is linear Rec.709
// (the config's scene_linear role); output is the "sRGB" display's encoding.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

// The display every preview goes to.
inline constexpr std::string_view preview_display = "sRGB";

// Loads and validates an OCIO config (empty path: data_file("ocio/config.ocio")); configs are
// cached per path, so repeated calls are cheap and thread-safe. Throws sylva::Error("path: why").
void validate_ocio_config(const std::filesystem::path& config = {});

// The views of the preview display, in the config's order (e.g. "Standard", "ACES", "Raw").
std::vector<std::string> ocio_views(const std::filesystem::path& config = {});

// Throws sylva::Error unless `view` is a view of the preview display (naming the available ones).
void check_preview_view(std::string_view view, const std::filesystem::path& config = {});

// Applies scene_linear → display "sRGB" / `view` in place to `pixel_count` interleaved RGB floats.
// The output is display code values, nominally in [0, 1] (not clamped). Throws sylva::Error for an
// unknown view (naming the available ones).
void apply_display_transform(float* rgb, size_t pixel_count, std::string_view view,
                             const std::filesystem::path& config = {});

}  // namespace sylva
