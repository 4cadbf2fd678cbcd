#include "scenes/sections/vegetation.h"

#include "core/error.h"
#include "geometry/placement.h"
#include "scenes/forest_rasters.h"
#include "scenes/sections/tree_variant_cache.h"

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace sylva {

namespace {

// The [[vegetation.species]] entries: a placement rule per entry, and its variants (seeds) as
// tree variants of their own ([vegetation] shares no prototypes), entry by entry.
struct Entries {
  std::vector<SpeciesPlacement> rules;
  std::vector<TreeVariantSpec> variants;
  std::vector<size_t> entry_of;                    // of each variant
  std::vector<std::vector<size_t>> variant_index;  // (entry, k-th variant) → variants
  std::vector<uint32_t> class_ids;                 // of each entry
  uint32_t bits_used = 0;
};

// One entry's rule, and its variants appended to `out`.
SpeciesPlacement read_entry(const Params& e, SceneBuilder& b, Entries& out) {
  e.check_keys({"bit", "species", "name", "seed", "bark", "leaf", "dead_bark", "quality", "density", "min_spacing",
                "variants", "scale"});
  if (!e.has("bit")) e.fail("[[vegetation.species]] needs bit = 0..13 (its feature-map bit)");
  SpeciesPlacement rule;
  rule.bit = static_cast<int>(e.integer("bit", 0, 0, kFeatureTreeBits - 1));
  if (out.bits_used >> rule.bit & 1u) e.fail("bit", fmt::format("bit {} names two species", rule.bit));
  out.bits_used |= 1u << rule.bit;
  TreeVariantSpec spec;
  spec.table = &e;
  spec.file = e.file_path("species");
  spec.species = &b.load_species_once(spec.file);
  if (std::holds_alternative<FournierGrindalParams>(spec.species->model))
    e.fail("species", "a Fournier–Grindal species cannot be placed from a feature map (it has no trunk mesh)");
  out.class_ids.push_back(b.class_of(spec.species->name, e, "species"));
  spec.materials = tree_materials(e, *spec.species, true, b);
  spec.options.quality = e.real("quality", 1.0, 0.01, 100.0);
  if (b.options().time_s) spec.options.time_s = *b.options().time_s;
  rule.density_per_ha = e.real("density", 100.0, 0.0, 1e6);
  rule.min_spacing_m = e.real("min_spacing", 2.0, 0.01, 1e4);
  if (rule.density_per_ha > 0 && std::sqrt(1e4 / rule.density_per_ha) <= rule.min_spacing_m)
    e.fail("density", fmt::format("a density of {:g} trees/ha cannot keep min_spacing = {:g} m (at most {:g})",
                                  rule.density_per_ha, rule.min_spacing_m, 1e4 / sqr(rule.min_spacing_m)));
  rule.scale_range = read_range(e, "scale", Vec2(1.0f), 1e-3, 1e3);
  const int count = static_cast<int>(e.integer("variants", 1, 1, 1000));
  const uint64_t first_seed = static_cast<uint64_t>(e.integer("seed", 1, 0, INT64_MAX - 1000));
  for (int k = 0; k < count; ++k) {
    spec.seed = first_seed + static_cast<uint64_t>(k);
    spec.key = fmt::format("vegetation|{}|{}|{}", out.rules.size(), spec.file.string(), spec.seed);
    out.entry_of.push_back(out.rules.size());
    out.variants.push_back(spec);
  }
  return rule;
}

// Every variant generated once, in parallel (results, and the first error in entry order, do not
// depend on the thread count), measured for its footprint and added to the cache; their
// `id.variant`s.
std::vector<uint32_t> add_variants(Entries& entries, SceneBuilder& b) {
  std::vector<const TreeVariantSpec*> specs;
  for (const TreeVariantSpec& s : entries.variants) specs.push_back(&s);
  std::vector<GeneratedTree> trees = b.tree_variants().generate(specs);
  std::vector<uint32_t> ids;
  entries.variant_index.resize(entries.rules.size());
  for (size_t v = 0; v < entries.variants.size(); ++v) {
    TreeVariantSpec& s = entries.variants[v];
    const size_t entry = entries.entry_of[v];
    GeneratedTree& tree = trees[v];
    if (!tree.error.empty()) s.table->fail("species", s.file.string() + ": " + tree.error);
    // The footprint: the widest bark vertex within 10 cm of the ground (flare and lobes included).
    float radius = 0.0f;
    for (const Vec3& p : tree.mesh.stems.positions)
      if (p.z < 0.1f) radius = std::max(radius, glm::length(Vec2(p)));
    entries.rules[entry].trunk_radius_m.push_back(radius);
    s.name = fmt::format("{} seed {}", s.table->string("name", s.species->name), s.seed);
    b.tree_variants().add(s, tree, b.lod.enabled);
    entries.variant_index[entry].push_back(v);
    ids.push_back(b.variant_of(s.key, {"tree", s.species->name, s.file.string(), s.seed, entries.class_ids[entry]}));
  }
  return ids;
}

// The feature map: a 16-bit image (`feature_map`) or a procedural one over the terrain's extent.
FeatureMap read_feature_map_of(const Params& t, const Entries& entries, uint64_t seed, const SceneBuilder& b) {
  if (!t.has("feature_map")) {
    ProceduralFeatureParams pf;
    pf.min_m = b.extent_min;
    pf.max_m = b.extent_max;
    pf.pixel_m = t.real("feature_resolution", pf.pixel_m, 0.01, 1e4);
    pf.patch_m = t.real("patch_size", pf.patch_m, 0.1, 1e6);
    pf.tree_cover = t.real("tree_cover", pf.tree_cover, 0.0, 1.0);
    pf.grass_cover = t.real("grass_cover", pf.grass_cover, 0.0, 1.0);
    for (const SpeciesPlacement& r : entries.rules) pf.tree_bits.push_back(r.bit);
    pf.grass_types = static_cast<int>(b.grass.size());
    pf.seed = seed;
    if (static_cast<double>((pf.max_m.x - pf.min_m.x) / pf.pixel_m) * ((pf.max_m.y - pf.min_m.y) / pf.pixel_m) >
        kMaxTerrainNodes)
      t.fail("feature_resolution", "the procedural feature map would be too large: raise feature_resolution");
    return make_procedural_feature_map(pf);
  }
  for (const char* key : {"feature_resolution", "patch_size", "tree_cover", "grass_cover"})
    if (t.has(key)) t.fail(key, fmt::format("'{}' is for a procedural feature map (one without 'feature_map')", key));
  const std::filesystem::path file = t.file_path("feature_map");
  FeatureMap map;
  try {
    map = read_feature_map(file, b.extent_min, b.extent_max);
  } catch (const ParseError&) {
    throw;
  } catch (const Error& e) {
    t.fail("feature_map", e.what());
  }
  uint32_t present = 0;
  for (const uint16_t v : map.bits) present |= v;
  for (int bit = 0; bit < kFeatureTreeBits; ++bit)
    if ((present >> bit & 1u) && !(entries.bits_used >> bit & 1u))
      t.fail("feature_map",
             fmt::format("{}: bit {} is set but no [[vegetation.species]] has bit = {}", file.string(), bit, bit));
  for (const uint16_t v : map.bits)
    if (grass_type(v) > static_cast<int>(b.grass.size()))
      t.fail("feature_map", fmt::format("{}: grass type {} is used but only {} [[grass]] type(s) are declared",
                                        file.string(), grass_type(v), b.grass.size()));
  return map;
}

// The placed trees, one instance per prototype of their variant (at its level of detail under
// [lod]), with object ids from `first_object_id` (after every id used so far by default).
void add_trees(const Params& t, const Entries& entries, const std::vector<PlacedTree>& trees,
               const std::vector<uint32_t>& variant_ids, SceneBuilder& b) {
  uint32_t next_id = 1;
  for (const Instance& inst : b.scene().instances) next_id = std::max(next_id, inst.object_id + 1);
  const int64_t first_id = t.integer("first_object_id", next_id, 1, 1 << 24);
  if (first_id + static_cast<int64_t>(trees.size()) > (int64_t{1} << 24))
    t.fail("first_object_id",
           fmt::format("{} trees from object id {} exceed the largest id, 2^24", trees.size(), first_id));
  const auto placed = [&](size_t i) {
    Mat4 m = glm::translate(Mat4(1.0f), trees[i].base_m);
    m = glm::rotate(m, trees[i].heading_rad, Vec3(0, 0, 1));
    return glm::scale(m, Vec3(trees[i].scale));
  };
  std::vector<const TreeVariantSpec*> specs;
  for (const TreeVariantSpec& s : entries.variants) specs.push_back(&s);
  std::vector<uint32_t> variant(trees.size());
  for (size_t i = 0; i < trees.size(); ++i)
    variant[i] = static_cast<uint32_t>(entries.variant_index[trees[i].species][trees[i].variant]);
  const std::vector<const std::vector<uint32_t>*> protos = b.tree_variants().draw(specs, variant, placed);
  std::vector<Instance>& instances = b.scene().instances;
  instances.reserve(instances.size() + trees.size());
  for (size_t i = 0; i < trees.size(); ++i) {
    const Mat4 m = placed(i);
    for (const uint32_t proto : *protos[i])
      instances.push_back(Instance{proto, m, static_cast<uint32_t>(first_id + static_cast<int64_t>(i)),
                                   entries.class_ids[trees[i].species], variant_ids[variant[i]]});
  }
}

// The grass patches of the feature map's grass types, onto the local slope.
void add_grass(const FeatureMap& map, uint64_t seed, SceneBuilder& b) {
  std::vector<float> patch_sizes;
  for (const SceneBuilder::GrassType& g : b.grass) patch_sizes.push_back(g.patch_size_m);
  for (const PlacedPatch& patch : place_grass_patches(map, *b.terrain, patch_sizes, seed)) {
    // Onto the local slope: z += slope · (x, y), blades stay vertical; then the heading.
    Mat4 shear(1.0f);
    shear[0][2] = patch.slope.x;
    shear[1][2] = patch.slope.y;
    const Mat4 m =
        glm::translate(Mat4(1.0f), patch.centre_m) * shear * glm::rotate(Mat4(1.0f), patch.heading_rad, Vec3(0, 0, 1));
    b.scene().instances.push_back(
        Instance{b.grass[static_cast<size_t>(patch.grass_type - 1)].prototype, m, 0, kClassGrass, 0});
  }
}

}  // namespace

void parse_vegetation(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("vegetation");
  t->check_keys({"feature_map", "seed", "first_object_id", "feature_resolution", "patch_size", "tree_cover",
                 "grass_cover", "species"});
  if (!b.terrain) t->fail("[vegetation] needs a [terrain] to place on");
  const uint64_t seed = static_cast<uint64_t>(t->integer("seed", 1, 0, INT64_MAX));
  Entries entries;
  if (t->has("species"))
    for (const Params* e : t->tables("species")) entries.rules.push_back(read_entry(*e, b, entries));
  const std::vector<uint32_t> variant_ids = add_variants(entries, b);
  const FeatureMap map = read_feature_map_of(*t, entries, seed, b);
  std::vector<PlacedTree> trees;
  try {
    trees = place_trees(map, *b.terrain, entries.rules, seed);
  } catch (const Error& e) {
    t->fail(e.what());
  }
  add_trees(*t, entries, trees, variant_ids, b);
  add_grass(map, seed, b);
}

}  // namespace sylva
