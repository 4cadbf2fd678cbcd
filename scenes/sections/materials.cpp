#include "scenes/sections/materials.h"

#include "render/materials/material.h"

namespace sylva {

void parse_materials(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("materials");
  for (const std::string& name : t->names()) {
    const Params* m = t->table(name);
    if (b.find_material(name)) m->fail("material '" + name + "' is defined twice");
    b.add_material(name, create_material(name, m->with_where("material '" + name + "'")));
  }
}

}  // namespace sylva
