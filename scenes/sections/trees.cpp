#include "scenes/sections/trees.h"

#include "core/error.h"
#include "core/rgb_spectrum.h"
#include "render/materials/material.h"
#include "scenes/sections/tree_variant_cache.h"

#include <fmt/core.h>

namespace sylva {

namespace {

// A Fournier–Grindal tree: one prototype holding its solids (trunk, crown), made once per
// (species, seed, materials). `bark` and `leaf` are optional: without them the species' §5 bark
// palette and §4 crown palette become diffuse reflectances (Smits up-sampling), the paper's
// opaque textured surface.
void place_solid_tree(const Params& t, const Species& species, const FournierGrindalParams& fg, uint64_t seed,
                      SceneBuilder& b) {
  if (t.has("flower")) t.fail("flower", "'flower' is for models with flowers (TREE-MAKER templates)");
  if (t.has("dead_bark")) t.fail("dead_bark", "'dead_bark' is for models with dead branches");
  const auto palette = [&](const char* key, const std::string& what, const std::vector<Vec3>& rgb) {
    if (t.has(key)) return std::vector<uint32_t>{b.material_ref(t, key)};
    std::vector<uint32_t> ids;
    for (size_t i = 0; i < rgb.size(); ++i) {
      const std::string name = fmt::format("{} {} colour {} ({:.3f}, {:.3f}, {:.3f})", species.file.string(), what, i,
                                           rgb[i].x, rgb[i].y, rgb[i].z);
      const std::optional<uint32_t> found = b.find_material(name);
      ids.push_back(found ? *found : b.add_material(name, make_diffuse(name, rgb_to_reflectance(rgb[i]))));
    }
    return ids;
  };
  const std::vector<uint32_t> bark = palette("bark", "bark", fournier_grindal_bark_palette(fg, seed));
  if (fg.leaf_area_density > 0.0f && !t.has("leaf"))
    t.fail("a turbid crown (optics = \"turbid\") needs 'leaf': the leaves' reflectance and transmittance");
  const std::vector<uint32_t> crown = palette("leaf", "crown", fg.crown_rgb);
  std::string key = fmt::format("{}|{}|solids", species.file.string(), seed);
  for (const uint32_t m : bark) key += fmt::format("|{}", m);
  for (const uint32_t m : crown) key += fmt::format("|c{}", m);
  TreeVariantCache& cache = b.tree_variants();
  const std::vector<uint32_t>* protos = cache.find(key);
  if (protos == nullptr) {
    Prototype p;
    p.name = t.string("name", species.name);
    try {
      p.solids = make_tree(fg, seed, TreeOptions{}).solids;
    } catch (const Error& e) {
      t.fail(species.file.string() + ": " + e.what());
    }
    for (const HalfSpaceSolid& solid : p.solids) p.solid_palettes.push_back(solid.material_slot == 0 ? bark : crown);
    protos = &cache.insert(key, {b.scene().add_prototype(std::move(p))});
  }
  const uint32_t class_id = b.class_of(species.name, t, "species");
  const uint32_t variant_id = b.variant_of(key, {"tree", species.name, species.file.string(), seed, class_id});
  for (const uint32_t proto : *protos) b.place(t, proto, class_id, variant_id);
}

// The variant a [[trees]] table names (its species is not Fournier–Grindal's): options, leaves and
// materials as read.
TreeVariantSpec read_tree(const Params& t, const Species& species, const std::filesystem::path& file, uint64_t seed,
                          const TreeOptions& options, bool with_leaves, SceneBuilder& b) {
  TreeVariantSpec spec;
  spec.table = &t;
  spec.species = &species;
  spec.file = file;
  spec.seed = seed;
  spec.options = options;
  spec.with_leaves = with_leaves;
  spec.materials = tree_materials(t, species, with_leaves, b);
  spec.key = tree_variant_key(spec, t);
  // The name is read when prototypes may be made (a new variant, or new levels of detail).
  if (b.lod.enabled || !b.tree_variants().has(spec.key)) spec.name = t.string("name", species.name);
  return spec;
}

// Every copy of a [[trees]] table (SceneBuilder::placements) at the level its own distance calls
// for (docs/lod.md).
void place_tree_levels(const Params& t, const TreeVariantSpec& spec, uint32_t class_id, uint32_t variant_id,
                       SceneBuilder& b) {
  const std::vector<SceneBuilder::Placed> copies = b.placements(t);
  const std::vector<const std::vector<uint32_t>*> protos = b.tree_variants().draw(
      {&spec}, std::vector<uint32_t>(copies.size(), 0), [&](size_t c) { return copies[c].world_from_object; });
  for (size_t c = 0; c < copies.size(); ++c)
    for (const uint32_t proto : *protos[c])
      b.scene().instances.push_back(
          Instance{proto, copies[c].world_from_object, copies[c].object_id, class_id, variant_id});
}

}  // namespace

// [lod]: on when the table is present unless `enabled = false`; `bias` scales the ranges at which
// detail drops (2 = twice as far). Read after [render] and [camera], whose image height and field
// of view give each tree's calibrated range.
void parse_lod(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("lod");
  t->check_keys({"enabled", "bias"});
  b.lod.enabled = t->boolean("enabled", true);
  b.lod.bias = t->real("bias", 1.0, 1e-3, 1e3);
}

// [[trees]]: leaves in material slot 0 take `leaf`, those in slots ≥ 1 (TREE-MAKER flowers and
// fruit) `flower`; each slot is its own prototype placed with the tree. A TREE-MAKER species may
// omit `bark`, `leaf` and `flower`: its template's colours are used.
void parse_trees(const Params& root, SceneBuilder& b) {
  for (const Params* t : root.tables("trees")) {
    t->check_keys({"name", "species", "seed", "bark", "dead_bark", "leaf", "flower", "leaves", "quality", "time",
                   "wind", "years", "translate", "rotate", "scale", "object_id", "instances", "tile"});
    const std::filesystem::path file = t->file_path("species");
    TreeOptions options;
    options.quality = t->real("quality", 1.0, 0.01, 100.0);
    options.time_s = t->real("time", 0.0, -1e9, 1e9);
    options.years = static_cast<int>(t->integer("years", 0, 0, 500));
    if (b.options().time_s) options.time_s = *b.options().time_s;
    const Vec2 wind = t->vec2("wind", Vec2(0.0f));
    if (wind.x < 0 || wind.y < 0) t->fail("wind", "wind = [speed, gust] must not be negative");
    options.wind_speed = wind.x;
    options.wind_gust = wind.y;
    const uint64_t seed = static_cast<uint64_t>(t->integer("seed", 1, 0, INT64_MAX));
    // `leaves = false`: the stems only (a bare tree, e.g. for a silhouette of the branching).
    const bool with_leaves = t->boolean("leaves", true);
    const Species& species = b.load_species_once(file);
    if (const auto* fg = std::get_if<FournierGrindalParams>(&species.model)) {
      place_solid_tree(*t, species, *fg, seed, b);
      continue;
    }
    const TreeVariantSpec spec = read_tree(*t, species, file, seed, options, with_leaves, b);
    TreeVariantCache& cache = b.tree_variants();
    if (!cache.has(spec.key)) {
      std::vector<GeneratedTree> tree = cache.generate({&spec});
      if (!tree[0].error.empty()) t->fail(file.string() + ": " + tree[0].error);
      cache.add(spec, tree[0], false);
    }
    const uint32_t class_id = b.class_of(species.name, *t, "species");
    const uint32_t variant_id = b.variant_of(spec.key, {"tree", species.name, file.string(), seed, class_id});
    if (b.lod.enabled) {
      place_tree_levels(*t, spec, class_id, variant_id, b);
    } else {
      for (const uint32_t proto : *cache.draw({&spec}, {0}, {})[0]) b.place(*t, proto, class_id, variant_id);
    }
  }
}

}  // namespace sylva
