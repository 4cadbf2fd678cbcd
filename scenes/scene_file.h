#pragma once
// Scene files (TOML): camera, sun, sky, materials, meshes (primitives or OBJ/PLY) with instances,
// trees from species files, render settings, bands and outputs. The schema is documented in
// docs/scene_format.md. Every mistake is reported as `file:line: what was expected`.

#include "core/band.h"
#include "core/image.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/sensors/plot_sensor.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sylva {

struct OutputSection {
  std::filesystem::path exr;  // empty: chosen on the command line
  std::filesystem::path png;
  float exposure_ev = 0.0f;   // added to the automatic exposure of the preview
  bool auto_exposure = true;  // meter the preview on the image (median luminance → mid grey)
  std::string view = "Standard";
};

// A row of the variant table (`id.variant` = row + 1): one generated tree (species + seed +
// options) or one target mesh, made once and instanced.
struct VariantInfo {
  std::string kind;    // "tree" or "target"
  std::string name;    // species name or target mesh name
  std::string source;  // species file or mesh file, as resolved
  uint64_t seed = 0;   // trees: the generator's seed
  uint32_t class_id = 0;
};

// A [[targets]] entry as placed: its instance and labels, for the JSON sidecar (scenes/sidecar.h).
struct TargetInfo {
  std::string name;
  uint32_t instance = 0;  // index in Scene::instances
  uint32_t object_id = 0;
  uint32_t class_id = 0;
  uint32_t variant_id = 0;
  Vec3 position{0.0f};  // world position of the mesh origin, after snapping
  float heading_deg = 0;
};

struct SceneFile {
  std::filesystem::path path;  // empty for the built-in default scene
  Scene scene;
  // [render]: resolution, spp, seed, depth (RenderSettings' defaults are the only defaults; the
  // bands are resolved by render_settings()), and the band names.
  RenderSettings render;
  std::vector<std::string> bands{"rgb", "nir"};
  OutputSection output;
  // [plot]: the plot sensor's view directions, sample counts and ground materials (the rectangle
  // and `cyclic` are in scene.plot).
  PlotSettings plot;
  std::vector<Band> custom_bands;  // [[bands]] tables: user SRFs, resolved by name before built-ins
  // Every file the scene read: the scene file itself (when loaded from one), then meshes, tables,
  // species files and templates (resolved paths). Outputs may not be any of them.
  std::vector<std::filesystem::path> inputs;
  // Of the file text and of every file it read (docs/design.md §8, scene_hash), hex.
  std::string content_hash;
  std::vector<std::string> warnings;  // "file:line: warning: ..." from species files it reads
  std::vector<VariantInfo> variants;  // the `id.variant` table (row i is variant i + 1)
  std::vector<TargetInfo> targets;    // [[targets]], in file order
};

// The largest camera coordinate (m, any axis) a scene may use: single-precision rays lose their
// precision beyond it (docs/limits.md).
inline constexpr float kMaxSceneCoordinate_m = 1e7f;

// The most nodes a terrain (after `step`) or a procedural feature map may have: 2^26, about
// 1.5 GiB of mesh (docs/limits.md).
inline constexpr double kMaxTerrainNodes = 67108864.0;

// How to assemble a scene beyond what its file says.
struct SceneOptions {
  // The time (s) of every [[trees]] table's wind sway, replacing its `time`: a frame of a wind
  // animation (`sylva render --frames`). Part of the content hash, so checkpoints and partial
  // renders of different frames never mix.
  std::optional<double> time_s;
  // The image size the scene will be rendered at (`--res`), replacing [render] width and height:
  // the level of detail of [vegetation] and [[placements]] trees is chosen for it (docs/lod.md).
  std::optional<std::pair<int, int>> resolution;
  // `section.key=value` overrides of the file's TOML (`--set`, scenes/toml_reader.h), applied in
  // order before any section reads it. Part of the content hash.
  std::vector<std::string> overrides;
};

// A tree's dead branches (TreeStems::dead) get the [[trees]] entry's `dead_bark` material, else a
// copy of its bark with the reflectance scaled by this factor.
inline constexpr float kDeadBarkReflectanceScale = 0.5f;

// Throws ParseError (file:line: ...) for any mistake in the file or in files it references.
SceneFile load_scene_file(const std::filesystem::path& file, const SceneOptions& options = {});
// Parses scene text; `name` is used in messages and relative paths resolve against `base_dir`
// (then against Sylva's data directory).
SceneFile parse_scene(const std::string& text, const std::string& name, const std::filesystem::path& base_dir,
                      const SceneOptions& options = {});
// The built-in default scene: ground, a few objects and a canopy of leaves under sun and sky.
SceneFile default_scene(const SceneOptions& options = {});

// Resolves band names against the file's custom bands, then the built-in ones.
std::vector<Band> resolve_bands(const SceneFile& file, const std::vector<std::string>& names);

// The render settings the file asks for (resolution, spp, seed, depth, its bands): the one mapping
// from scene file to settings; the command line overrides fields of the result.
RenderSettings render_settings(const SceneFile& file);

// Records what produced an image in its header: sylva:version, spp, seed, scene, scene_hash,
// max_depth, bands (names of `settings.bands`) and units.
void annotate_render(Image& image, const SceneFile& file, const RenderSettings& settings);

}  // namespace sylva
