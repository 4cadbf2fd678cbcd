#include "pipeline/outputs.h"

#include "core/color.h"
#include "core/error.h"
#include "core/image.h"
#include "core/memory.h"
#include "core/output_paths.h"
#include "scenes/sidecar.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace sylva {

// Exposure for the preview: the median luminance of the visible band maps to 18% grey.
float auto_exposure_ev(const Image& image, const std::array<std::string, 3>& channels) {
  const int r = image.find_channel(channels[0]), g = image.find_channel(channels[1]),
            b = image.find_channel(channels[2]);
  std::vector<float> lum;
  lum.reserve(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float l = 0.2126f * image.at(x, y, r) + 0.7152f * image.at(x, y, g) + 0.0722f * image.at(x, y, b);
      if (l > 0 && std::isfinite(l)) lum.push_back(l);
    }
  if (lum.empty()) return 0.0f;
  std::nth_element(lum.begin(), lum.begin() + lum.size() / 2, lum.end());
  return std::log2(0.18f / lum[lum.size() / 2]);
}

void check_render_outputs(const RenderJob& job, const OutputPaths& paths, const PreviewOverrides& preview,
                          bool memory_check) {
  std::vector<OutputFile> outputs{
      {"-o", paths.exr}, {"--png", paths.png}, {"checkpoint", paths.checkpoint}, {"label sidecar", paths.sidecar}};
  check_outputs(outputs, job.file.inputs);
  if (!paths.png.empty()) check_preview_view(preview.view.empty() ? job.file.output.view : preview.view);
  if (!memory_check) return;
  const MemoryEstimate need = estimate_render_memory(job.file.scene, job.settings);
  const uint64_t available = available_memory_bytes();
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  if (need.total() > available)
    throw Error(fmt::format(
        "the render needs about {:.2f} GiB (film {:.2f}, image {:.2f}, BVH {:.2f}) but only {:.2f} "
        "GiB are available; lower --res or the number of bands, or try anyway with "
        "--no-memory-check (docs/limits.md)",
        need.total() / kGiB, need.film_bytes / kGiB, need.image_bytes / kGiB, need.bvh_bytes / kGiB, available / kGiB));
}

Image annotated_image(const Renderer& renderer, const Film& film, const SceneFile& file) {
  Image image = renderer.make_image(film);
  annotate_render(image, file, renderer.settings());
  return image;
}

void write_render_outputs(const Renderer& renderer, const Image& image, const SceneFile& file,
                          const std::filesystem::path& exr, const std::filesystem::path& png,
                          const PreviewOverrides& overrides) {
  write_exr(exr, image);
  write_sidecar(sidecar_path(exr), file, renderer.settings(), image, exr);
  if (png.empty()) return;
  write_render_preview(renderer, image, file.output, png, overrides);
}

void write_render_preview(const Renderer& renderer, const Image& image, const OutputSection& output,
                          const std::filesystem::path& png, const PreviewOverrides& overrides) {
  PreviewOptions preview;
  if (image.find_channel("R") < 0) {
    const std::string grey = renderer.radiance_channels().front();
    preview.channels = {grey, grey, grey};
  }
  preview.view = overrides.view.empty() ? output.view : overrides.view;
  preview.exposure_ev = overrides.exposure_ev.value_or(output.exposure_ev) +
                        (output.auto_exposure ? auto_exposure_ev(image, preview.channels) : 0.0f);
  write_png_preview(png, image, preview);
}

}  // namespace sylva
