#include "scenes/sections/scene_sections.h"

#include "scenes/sections/camera.h"
#include "scenes/sections/materials.h"
#include "scenes/sections/meshes.h"
#include "scenes/sections/placements.h"
#include "scenes/sections/plot_canopies.h"
#include "scenes/sections/render_output.h"
#include "scenes/sections/sun_sky_haze.h"
#include "scenes/sections/targets.h"
#include "scenes/sections/terrain_grass.h"
#include "scenes/sections/trees.h"
#include "scenes/sections/vegetation.h"

#include <fmt/core.h>

#include <string>

namespace sylva {

std::span<const SceneSection> scene_sections() {
  // One row per section: its name in the file and its reader.
  static constexpr SceneSection kSections[] = {
      {"render", &parse_render},
      {"bands", &parse_bands},
      {"camera", &parse_camera},
      {"lod", &parse_lod},
      {"sun", &parse_sun},
      {"sky", &parse_sky},
      {"haze", &parse_haze},
      {"materials", &parse_materials},
      {"plot", &parse_plot},
      {"meshes", &parse_meshes},
      {"trees", &parse_trees},
      {"leaves", &parse_leaves},
      {"canopies", &parse_canopies},
      {"terrain", &parse_terrain},
      {"grass", &parse_grass},
      {"vegetation", &parse_vegetation},
      {"placements", &parse_placements},
      {"targets", &parse_targets},
      {"output", &parse_output},
      {"sensor", &parse_sensor},
  };
  return kSections;
}

void read_scene_sections(SceneBuilder& builder) {
  const Params& root = builder.root();
  const std::span<const SceneSection> sections = scene_sections();
  for (const std::string& name : root.names()) {
    bool known = false;
    for (const SceneSection& s : sections) known = known || s.name == name;
    if (!known) {
      std::string list;
      for (const SceneSection& s : sections) list += (list.empty() ? "" : ", ") + std::string(s.name);
      root.fail(name, fmt::format("unknown key '{}' in the scene (expected one of: {})", name, list));
    }
  }
  for (const SceneSection& s : sections)
    if (root.has(s.name)) s.read(root, builder);
}

}  // namespace sylva
