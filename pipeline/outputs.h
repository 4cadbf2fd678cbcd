#pragma once
// The output stage of the render call: the checks made before any work (output paths against each
// other and the scene's inputs, the preview's view, the memory the render needs), and the outputs
// of a finished film: the annotated image, its EXR, label sidecar and PNG preview, each written
// atomically (core/atomic_file.h).

#include "pipeline/scene_request.h"

#include <array>
#include <filesystem>
#include <optional>
#include <string>

namespace sylva {

struct PreviewOverrides {
  std::optional<float> exposure_ev;  // replaces the scene's [output] exposure
  std::string view;                  // replaces the scene's [output] view when not empty
};

// What a render writes. An empty path is not written.
struct OutputPaths {
  std::filesystem::path exr;         // the EXR, or the partial file of a chunk
  std::filesystem::path png;         // its preview
  std::filesystem::path checkpoint;  // the render's checkpoint (kept when interrupted)
  std::filesystem::path sidecar;     // the label sidecar (scenes/sidecar.h)
};

// Everything that can be checked before the scene's BVH is built and a sample rendered: the outputs
// (core/output_paths.h) against each other and every input of the scene, the preview's view, and
// (with `memory_check`) the memory the render needs against what is available. Throws sylva::Error.
void check_render_outputs(const RenderJob& job, const OutputPaths& outputs, const PreviewOverrides& preview,
                          bool memory_check);

// The film as an image with the render's header (annotate_render, with the renderer's settings).
Image annotated_image(const Renderer& renderer, const Film& film, const SceneFile& file);

// `image` (annotated_image) as the EXR, its label sidecar and, if `png` is not empty, its preview.
void write_render_outputs(const Renderer& renderer, const Image& image, const SceneFile& file,
                          const std::filesystem::path& exr, const std::filesystem::path& png,
                          const PreviewOverrides& preview);

// The exposure (stops) that maps the median luminance of `channels` (linear Rec.709) to 18 % grey:
// the previews' auto exposure ([output] auto_exposure; sylva denoise --png).
float auto_exposure_ev(const Image& image, const std::array<std::string, 3>& channels);

// The PNG preview alone of an image made by `renderer` (the visible band, else its first band as
// grey), with the scene's [output] view and exposure.
void write_render_preview(const Renderer& renderer, const Image& image, const OutputSection& output,
                          const std::filesystem::path& png, const PreviewOverrides& overrides);

}  // namespace sylva
