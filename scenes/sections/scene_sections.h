#pragma once
// The table of scene-file sections: each top-level TOML key names one section, read by its family's
// function (scenes/sections/<family>.h) into the scene builder. Adding a section is its reader in
// its family's file and one row of the table in scene_sections.cpp (docs/design.md §3).

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

#include <span>
#include <string_view>

namespace sylva {

// Reads the section `root` holds (root.table(name) or root.tables(name)) into the builder.
using SectionReader = void (*)(const Params& root, SceneBuilder& builder);

struct SceneSection {
  std::string_view name;
  SectionReader read;
};

// Every section, in the order they are read (materials before the meshes and trees that use
// them, [plot] before the tiles that need its size, [terrain] before what stands on it).
std::span<const SceneSection> scene_sections();

// Rejects unknown top-level keys ("unknown key 'x' in the scene (expected one of: ...)") and reads
// every section the document has, in table order.
void read_scene_sections(SceneBuilder& builder);

}  // namespace sylva
