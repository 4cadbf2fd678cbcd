#include "scenes/scene_file.h"

#include "core/data_path.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "scenes/sections/scene_builder.h"
#include "scenes/sections/scene_sections.h"
#include "scenes/toml_reader.h"
#include "scenes/view_metadata.h"

#include <fmt/core.h>

#include <algorithm>
#include <memory>
#include <variant>

namespace sylva {

namespace {

const char* const kDefaultSceneText =
#include "scenes/default_scene.inc"
    ;

// Relative file names resolve against the scene's directory, then Sylva's data directory
// (find_named_file). Every file found is appended to `found` (in order, repeats included), so the
// scene hash can cover it.
FileResolver file_resolver(const std::filesystem::path& base_dir,
                           const std::shared_ptr<std::vector<std::filesystem::path>>& found) {
  return [base_dir, found](const std::string& rel) {
    FileLookup lookup = find_named_file(base_dir, rel);
    if (!lookup.found.empty()) found->push_back(lookup.found);
    return lookup;
  };
}

}  // namespace

SceneFile parse_scene(const std::string& text, const std::string& name, const std::filesystem::path& base_dir,
                      const SceneOptions& options) {
  TomlReader reader(name);
  toml::table document = reader.parse(text);
  apply_overrides(document, options.overrides);
  const auto found = std::make_shared<std::vector<std::filesystem::path>>();
  const Params root = reader.to_params(document, "the scene", file_resolver(base_dir, found));
  SceneBuilder builder(root, options);
  read_scene_sections(builder);
  // The species files (and their templates) are chained first, as read; then every other file the
  // scene read (meshes, spectrum and SRF tables), each once, in the order first named. So editing
  // any input changes the hash, and a checkpoint or golden record of the old scene is refused.
  uint64_t dependencies = builder.dependency_hash();
  SceneFile file = builder.finish();
  std::vector<std::filesystem::path> hashed;
  for (const std::filesystem::path& f : *found) {
    if (builder.species().count(f.string()) > 0 || std::find(hashed.begin(), hashed.end(), f) != hashed.end()) continue;
    hashed.push_back(f);
    dependencies = hash_ids(dependencies, mix64(fnv1a64_of_file(f, kMaxMeshFileBytes, "scene input")));
    file.inputs.push_back(f);
  }
  for (const auto& [species_file, species] : builder.species()) {
    file.inputs.emplace_back(species_file);
    if (const auto* tm = std::get_if<TreeMakerTemplate>(&species.model); tm != nullptr && tm->source != species_file)
      file.inputs.push_back(tm->source);
  }
  uint64_t hash = hash_ids(hash_text(text), dependencies);
  if (options.time_s) hash = hash_ids(hash, hash_text(fmt::format("time {:a}", *options.time_s)));
  for (const std::string& o : options.overrides) hash = hash_ids(hash, hash_text("--set " + o));
  file.content_hash = hex64(hash);
  return file;
}

SceneFile load_scene_file(const std::filesystem::path& path, const SceneOptions& options) {
  const std::string text = read_input_file(path, kMaxSceneFileBytes, "scene file");
  SceneFile f = parse_scene(text, path.string(), path.parent_path().empty() ? "." : path.parent_path(), options);
  f.path = path;
  f.inputs.insert(f.inputs.begin(), path);
  return f;
}

SceneFile default_scene(const SceneOptions& options) {
  return parse_scene(kDefaultSceneText, "<default scene>", data_dir(), options);
}

std::vector<Band> resolve_bands(const SceneFile& file, const std::vector<std::string>& names) {
  std::vector<Band> bands;
  for (const std::string& n : names) {
    bool found = false;
    for (const Band& b : file.custom_bands)
      if (b.name == n) {
        bands.push_back(b);
        found = true;
      }
    if (!found) bands.push_back(resolve_band(n));
    for (size_t i = 0; i + 1 < bands.size(); ++i)
      if (bands[i].name == n) throw Error("band '" + n + "' is requested twice");
  }
  return bands;
}

RenderSettings render_settings(const SceneFile& file) {
  RenderSettings s = file.render;
  s.bands = resolve_bands(file, file.bands);
  return s;
}

void annotate_render(Image& image, const SceneFile& file, const RenderSettings& settings) {
  image.set_attribute("sylva:version", SYLVA_VERSION);
  image.set_attribute("sylva:spp", std::to_string(settings.spp));
  image.set_attribute("sylva:seed", std::to_string(settings.seed));
  image.set_attribute("sylva:sampler", sampler_name(settings.sampler));
  image.set_attribute("sylva:scene", file.path.empty() ? "<default scene>" : file.path.filename().string());
  image.set_attribute("sylva:scene_hash", file.content_hash);
  image.set_attribute("sylva:max_depth", std::to_string(settings.integrator.max_depth));
  if (settings.integrator.light_samples != 1)
    image.set_attribute("sylva:light_samples", std::to_string(settings.integrator.light_samples));
  // The kernels that traced it: renders agree bit for bit only on the same set (EmbreeIsa).
  image.set_attribute("sylva:embree_isa", embree_isa_name(resolve_embree_isa(settings.isa)));
  std::string bands;
  for (const Band& b : settings.bands) bands += (bands.empty() ? "" : ",") + b.name;
  image.set_attribute("sylva:bands", bands);
  image.set_attribute("sylva:quantity", quantity_name(settings.quantity));
  annotate_view(image, file.scene, settings.width, settings.height);
  // The band-weighted horizontal irradiance per channel: the divisor of the reflectance factor.
  const std::vector<float> e = channel_irradiance(Environment(file.scene.sun, file.scene.sky), settings.bands);
  std::string irradiance;
  size_t c = 0;
  for (const Band& b : settings.bands)
    for (const std::string& name : b.channels) {
      irradiance += fmt::format("{}{}={:.7g}", c ? "," : "", name, e[c]);
      ++c;
    }
  image.set_attribute("sylva:irradiance", irradiance);
  const std::string values =
      settings.quantity == Quantity::reflectance
          ? "band channels: reflectance factor pi L_c / E_c, E_c = band-weighted irradiance on a "
            "horizontal plane from the sun and sky (sylva:irradiance, W m^-2 nm^-1)"
          : "band channels: SRF-weighted mean spectral radiance, W m^-2 sr^-1 nm^-1";
  image.set_attribute("sylva:units",
                      values +
                          "; R,G,B: CIE 1931 XYZ (Y = luminance-weighted mean) in linear Rec.709 primaries; var.*: "
                          "variance of the pixel mean; Z: camera-space depth, m");
}

}  // namespace sylva
