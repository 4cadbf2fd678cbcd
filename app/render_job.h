#pragma once
// What `sylva render` and `sylva merge` share: turning a scene file and the command line's
// overrides into the render's settings, describing them in a partial file's header so `sylva
// merge` can rebuild the same render, and writing the EXR and its PNG preview.

#include "render/renderer.h"
#include "scenes/scene_file.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>

namespace sylva {

// The command line's say over a render; zero, negative or empty fields keep the scene file's value.
struct RenderRequest {
  std::string scene;  // scene file; empty: the built-in default scene
  std::string res;    // WIDTHxHEIGHT
  int spp = 0;
  int64_t seed = -1;
  std::string bands;  // comma-separated
  int max_depth = 0;
  std::string quantity;  // "radiance" or "reflectance"
  std::string isa;       // Embree's kernels (parse_embree_isa); empty: the scene file's
  int threads = 0;
  bool progress = false;
  std::optional<double> time_s;  // wind time of every tree (SceneOptions::time_s)
};

struct RenderJob {
  SceneFile file;
  RenderSettings settings;
};

// "WIDTHxHEIGHT" → {width, height}, each 1..kMaxImageSide; anything else (signs, overflow, extra
// characters) throws sylva::Error naming --res.
std::pair<int, int> parse_resolution(const std::string& text);

// Loads the scene and applies the overrides. Throws ParseError / sylva::Error.
RenderJob prepare_render(const RenderRequest& request);

// The fields of a partial file's job header that rebuild `request`'s render (scene as an absolute
// path, resolved settings), and back.
std::map<std::string, std::string> describe_job(const RenderRequest& request, const RenderJob& job);
RenderRequest request_from_job(const std::map<std::string, std::string>& fields, int spp);

struct PreviewOverrides {
  std::optional<float> exposure_ev;  // replaces the scene's [output] exposure
  std::string view;                  // replaces the scene's [output] view when not empty
};

// The annotated EXR of `film` (written atomically) and, if `png` is not empty, its preview.
void write_render_outputs(const Renderer& renderer, const Film& film, const RenderJob& job,
                          const std::filesystem::path& exr, const std::filesystem::path& png,
                          const PreviewOverrides& preview);

// The PNG preview alone of an image made by `renderer` (the visible band, else its first band as
// grey), with the scene's [output] view and exposure.
void write_render_preview(const Renderer& renderer, const Image& image, const OutputSection& output,
                          const std::filesystem::path& png, const PreviewOverrides& overrides);

}  // namespace sylva
