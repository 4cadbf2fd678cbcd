#pragma once
// [materials.NAME] tables: the material registry (render/materials/material.h) picks the type and
// the type reads its own parameters. Other sections refer to them by name
// (SceneBuilder::material_ref).

#include "core/params.h"
#include "scenes/sections/scene_builder.h"

namespace sylva {

void parse_materials(const Params& root, SceneBuilder& b);

}  // namespace sylva
