#pragma once
// The scene side of the render call (pipeline/render_call.h): a scene source (file, TOML text or
// the built-in default) and the caller's overrides turned into the scene and the render's settings,
// and described in a partial file's header so `sylva merge` can rebuild the same render.

#include "render/renderer.h"
#include "scenes/scene_file.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sylva {

// Where a scene comes from: a file; else TOML text (named `name` in messages, its relative paths
// resolved against the current directory, then Sylva's data directory); with both empty the
// built-in default scene (data/examples/default.toml, embedded in the binary).
struct SceneSource {
  std::string file;
  std::string text;
  std::string name = "<scene text>";

  static SceneSource from_file(std::string path) { return {std::move(path), {}, {}}; }
  static SceneSource from_text(std::string toml, std::string name = "<scene text>") {
    return {{}, std::move(toml), std::move(name)};
  }
  // How messages and headers name it: the file, the text's name or "<default scene>".
  std::string label() const;
};

// The caller's say over a render; zero, negative or empty fields keep the scene file's value.
struct RenderRequest {
  SceneSource source;
  std::string res;  // WIDTHxHEIGHT
  int spp = 0;
  int64_t seed = -1;
  std::string bands;  // comma-separated
  int max_depth = 0;
  std::string quantity;  // "radiance" or "reflectance"
  std::string isa;       // Embree's kernels (parse_embree_isa); empty: the scene file's
  int threads = 0;
  double noise_threshold = -1;  // adaptive sampling's relative error (RenderSettings); < 0: the file's
  std::string noise_channels;   // comma-separated band channels it applies to
  double time_limit_s = -1;     // seconds (RenderSettings::time_limit_s); < 0: the file's
  bool progress = false;
  bool features = false;         // gather the denoiser's features (RenderSettings::features)
  bool material_ids = false;     // write id.material (RenderSettings::material_ids)
  std::optional<double> time_s;  // wind time of every tree (SceneOptions::time_s)
  // `section.key=value` overrides of the scene's TOML (--set; SceneOptions::overrides).
  std::vector<std::string> overrides;
  // Trees made by earlier renders of this process (a study's frames; SceneOptions::tree_memo).
  std::shared_ptr<TreeMemo> tree_memo;
};

struct RenderJob {
  SceneFile file;
  RenderSettings settings;
};

// "WIDTHxHEIGHT" → {width, height}, each 1..kMaxImageSide; anything else (signs, overflow, extra
// characters) throws sylva::Error naming --res.
std::pair<int, int> parse_resolution(const std::string& text);

// Loads the scene (file, text or default). Throws ParseError / sylva::Error.
SceneFile load_scene(const SceneSource& source, const SceneOptions& options = {});

// Loads the scene and applies the overrides. Throws ParseError / sylva::Error.
RenderJob prepare_render(const RenderRequest& request);

// The fields of a partial file's job header that rebuild `request`'s render (scene as an absolute
// path, resolved settings), and back.
std::map<std::string, std::string> describe_job(const RenderRequest& request, const RenderSettings& settings);
RenderRequest request_from_job(const std::map<std::string, std::string>& fields, int spp);

}  // namespace sylva
