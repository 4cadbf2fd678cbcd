#pragma once
// The JSON sidecar of a render (docs/scene_format.md, "Label sidecar"): OUT.json next to OUT.exr,
// mapping the label AOVs' ids to names — the class table, the variant table (species, seed), every
// object visible in the image and every target (world position and bounds) — and giving for every
// target its image box, visible-pixel count and occlusion, read from the image's first-hit AOVs, so
// a detection study has ground truth without post-processing. Written with a small JSON writer.

#include "core/image.h"
#include "render/renderer.h"
#include "scenes/scene_file.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace sylva {

// A JSON string literal: quotes, backslash and control characters escaped (RFC 8259 §7).
std::string json_string(std::string_view s);

// OUT.exr → OUT.json (the extension replaced).
std::filesystem::path sidecar_path(const std::filesystem::path& exr);

// The sidecar of `image` (a whole-image render of `file` with `settings`, holding id.object and
// id.class): its text. `exr` is the image's file name as recorded in the sidecar. Renders each
// target alone once (render/coverage.h) for the unoccluded pixel counts.
std::string make_sidecar(const SceneFile& file, const RenderSettings& settings, const Image& image,
                         const std::filesystem::path& exr);

// make_sidecar written atomically to `path`.
void write_sidecar(const std::filesystem::path& path, const SceneFile& file, const RenderSettings& settings,
                   const Image& image, const std::filesystem::path& exr);

}  // namespace sylva
