#include "scenes/sections/placements.h"

#include "core/error.h"
#include "scenes/placement_list.h"
#include "scenes/sections/tree_variant_cache.h"

#include <fmt/core.h>

#include <cmath>
#include <functional>
#include <map>

namespace sylva {

namespace {

// A species the rows name: [placements.species.NAME] = { species, bark, leaf, ... }.
struct Kind {
  std::string name;
  TreeVariantSpec spec;  // its variants differ in seed and key
  uint32_t class_id = 0;
};

std::vector<Kind> read_kinds(const Params& t, SceneBuilder& b) {
  const Params* kinds_table = t.table("species");
  std::vector<Kind> kinds;
  for (const std::string& name : kinds_table->names()) {
    const Params* k = kinds_table->table(name);
    k->check_keys({"species", "bark", "dead_bark", "leaf", "flower", "leaves", "quality"});
    Kind kind;
    kind.name = name;
    TreeVariantSpec& s = kind.spec;
    s.table = k;
    s.file = k->file_path("species");
    s.species = &b.load_species_once(s.file);
    if (std::holds_alternative<FournierGrindalParams>(s.species->model))
      k->fail("species",
              "a Fournier-Grindal species (solids) is placed with [[trees]]; placement lists take meshed species");
    s.options.quality = k->real("quality", 1.0, 0.01, 100.0);
    if (b.options().time_s) s.options.time_s = *b.options().time_s;
    s.with_leaves = k->boolean("leaves", true);
    s.materials = tree_materials(*k, *s.species, s.with_leaves, b);
    s.name = s.species->name;
    kind.class_id = b.class_of(s.species->name, *k, "species");
    kinds.push_back(std::move(kind));
  }
  if (kinds.empty()) kinds_table->fail("[placements.species] needs at least one species: NAME = { species = ... }");
  return kinds;
}

// The rows, compactly, and the variants they use, keyed by (kind, seed) in first-listed order.
struct Rows {
  struct Row {
    float x, y, z, scale, heading_deg;
  };
  std::vector<Row> rows;
  std::vector<uint32_t> variant;  // of each row
  std::vector<std::pair<uint32_t, uint64_t>> variants;
  std::map<std::pair<uint32_t, uint64_t>, uint32_t> variant_index;

  void add(const PlacementRow& r, const std::vector<Kind>& kinds, const std::function<void(const std::string&)>& fail) {
    uint32_t kind = 0;
    while (kind < kinds.size() && kinds[kind].name != r.species) ++kind;
    if (kind == kinds.size()) {
      std::string known;
      for (const Kind& k : kinds) known += (known.empty() ? "" : ", ") + k.name;
      fail(fmt::format("unknown species '{}' (the [[placements]] entry names: {})", r.species, known));
    }
    auto [it, added] = variant_index.emplace(std::make_pair(kind, r.seed), static_cast<uint32_t>(variants.size()));
    if (added) variants.emplace_back(kind, r.seed);
    rows.push_back(Row{r.x, r.y, r.z, r.scale, r.heading_deg});
    variant.push_back(it->second);
  }

  // Translate · rotate by −heading about Z (a compass bearing turns clockwise) · scale.
  Mat4 world_from_object(size_t i) const {
    const Row& r = rows[i];
    const float heading = radians(r.heading_deg);
    const float c = std::cos(heading) * r.scale, sn = std::sin(heading) * r.scale;
    Mat4 m(1.0f);
    m[0] = Vec4(c, -sn, 0.0f, 0.0f);
    m[1] = Vec4(sn, c, 0.0f, 0.0f);
    m[2] = Vec4(0.0f, 0.0f, r.scale, 0.0f);
    m[3] = Vec4(r.x, r.y, r.z, 1.0f);
    return m;
  }
};

Rows read_rows(const Params& t, const std::vector<Kind>& kinds) {
  Rows rows;
  if (t.has("file")) {
    const std::filesystem::path list = t.file_path("file");
    for_each_placement_row(list, kMaxSceneCoordinate_m, [&](const PlacementRow& r, int line) {
      rows.add(r, kinds, [&](const std::string& what) { throw ParseError(list, line, what); });
    });
    return rows;
  }
  for (const Params* r : t.tables("rows")) {
    r->check_keys({"x", "y", "z", "species", "seed", "scale", "heading"});
    const double m = kMaxSceneCoordinate_m;
    const std::string species = r->string("species");
    PlacementRow row;
    row.x = static_cast<float>(r->number("x", 0.0, -m, m));
    row.y = static_cast<float>(r->number("y", 0.0, -m, m));
    row.z = static_cast<float>(r->number("z", 0.0, -m, m));
    if (!r->has("x") || !r->has("y")) r->fail("a placement row needs x and y");
    row.species = species;
    row.seed = static_cast<uint64_t>(r->integer("seed", 1, 0, INT64_MAX));
    row.scale = r->real("scale", 1.0, 1e-6, 1e4);
    row.heading_deg = r->real("heading", 0.0, -3600.0, 3600.0);
    rows.add(row, kinds, [&](const std::string& what) { r->fail("species", what); });
  }
  return rows;
}

// The variants of the rows as specs; those not cached are generated (in parallel) and added in
// first-listed order. Returns each variant's `id.variant`.
std::vector<uint32_t> add_variants(const std::vector<Kind>& kinds, const Rows& rows,
                                   std::vector<TreeVariantSpec>& specs, SceneBuilder& b) {
  TreeVariantCache& cache = b.tree_variants();
  std::vector<const TreeVariantSpec*> fresh;
  for (const auto& [kind, seed] : rows.variants) {
    TreeVariantSpec s = kinds[kind].spec;
    s.seed = seed;
    s.key = tree_variant_key(s, *s.table);
    specs.push_back(std::move(s));
  }
  for (const TreeVariantSpec& s : specs)
    if (!cache.has(s.key)) fresh.push_back(&s);
  std::vector<GeneratedTree> generated = cache.generate(fresh);
  std::vector<uint32_t> ids;
  size_t next = 0;
  for (size_t v = 0; v < specs.size(); ++v) {
    const TreeVariantSpec& s = specs[v];
    const Kind& kind = kinds[rows.variants[v].first];
    if (next < fresh.size() && fresh[next] == &s) {
      GeneratedTree& tree = generated[next++];
      if (!tree.error.empty())
        s.table->fail("species", fmt::format("{} (seed {}): {}", s.file.string(), s.seed, tree.error));
      cache.add(s, tree, false);
    }
    ids.push_back(b.variant_of(s.key, {"tree", s.species->name, s.file.string(), s.seed, kind.class_id}));
  }
  return ids;
}

}  // namespace

void parse_placements(const Params& root, SceneBuilder& b) {
  for (const Params* t : root.tables("placements")) {
    t->check_keys({"file", "rows", "species"});
    if (t->has("file") == t->has("rows")) t->fail("[[placements]] needs either file = \"list.csv\" or rows = [...]");
    const std::vector<Kind> kinds = read_kinds(*t, b);
    const Rows rows = read_rows(*t, kinds);
    std::vector<TreeVariantSpec> specs;
    const std::vector<uint32_t> variant_ids = add_variants(kinds, rows, specs, b);
    std::vector<const TreeVariantSpec*> spec_of;
    for (const TreeVariantSpec& s : specs) spec_of.push_back(&s);
    const std::vector<const std::vector<uint32_t>*> protos =
        b.tree_variants().draw(spec_of, rows.variant, [&](size_t i) { return rows.world_from_object(i); });

    std::vector<Instance>& instances = b.scene().instances;
    const size_t first = instances.size();
    size_t count = 0;
    for (const std::vector<uint32_t>* p : protos) count += p->size();
    instances.reserve(first + count);
    uint32_t object = 0;
    for (size_t i = 0; i < rows.rows.size(); ++i) {
      ++object;
      const Mat4 m = rows.world_from_object(i);
      const uint32_t v = rows.variant[i];
      const uint32_t class_id = kinds[rows.variants[v].first].class_id;
      for (const uint32_t proto : *protos[i]) instances.push_back(Instance{proto, m, object, class_id, variant_ids[v]});
    }
    if (object > kMaxObjectId) t->fail(fmt::format("more than {} placed trees", kMaxObjectId));
    b.add_automatic_ids(first, instances.size());
  }
}

}  // namespace sylva
