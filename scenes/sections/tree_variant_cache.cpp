#include "scenes/sections/tree_variant_cache.h"

#include "core/rgb_spectrum.h"
#include "render/materials/material.h"

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace sylva {

std::string tree_variant_key(const TreeVariantSpec& spec, const Params& t) {
  const TreeOptions& o = spec.options;
  std::string key = fmt::format("{}|{}|{}|{}|{}|{}|{}", spec.file.string(), spec.seed, o.quality, o.time_s,
                                o.wind_speed, o.wind_gust, spec.with_leaves);
  for (const uint32_t m : spec.materials) key += fmt::format("|{}", m);
  if (o.years > 0) key += fmt::format("|years {}", o.years);
  if (t.has("dead_bark")) key += "|dead " + t.string("dead_bark");
  return key;
}

std::vector<uint32_t> tree_materials(const Params& t, const Species& species, bool with_leaves, SceneBuilder& b) {
  const TreeMakerTemplate* tm = std::get_if<TreeMakerTemplate>(&species.model);
  if (tm == nullptr) {
    if (t.has("flower")) t.fail("flower", "'flower' is for models with flowers (TREE-MAKER templates)");
    const uint32_t bark = b.material_ref(t, "bark");
    return {bark, with_leaves || t.has("leaf") ? b.material_ref(t, "leaf") : bark};
  }
  const TreeMakerMaterials colours = treemaker_materials(*tm);
  const auto from_template = [&](const std::string& what, bool leaf, const Vec3& rgb) {
    const std::string name = fmt::format("{} {} (template colour)", species.file.string(), what);
    if (const std::optional<uint32_t> found = b.find_material(name)) return *found;
    const DenseSpectrum rho = rgb_to_reflectance(rgb);
    return b.add_material(name,
                          leaf ? Material(make_leaf(name, rho, DenseSpectrum())) : Material(make_diffuse(name, rho)));
  };
  std::vector<uint32_t> out;
  out.push_back(t.has("bark") ? b.material_ref(t, "bark") : from_template("bark", false, colours.bark_rgb));
  for (size_t slot = 0; slot < std::max<size_t>(colours.element_rgb.size(), 1); ++slot) {
    const char* key = slot == 0 ? "leaf" : "flower";
    if (t.has(key)) {
      out.push_back(b.material_ref(t, key));
      if (slot > 0) break;  // a named flower material takes every slot beyond the leaves
    } else {
      const Vec3 rgb = slot < colours.element_rgb.size() ? colours.element_rgb[slot] : Vec3(0.5f);
      const std::string what = slot < colours.element_color_names.size() ? colours.element_color_names[slot] : "leaf";
      out.push_back(from_template(what, true, rgb));
    }
  }
  return out;
}

std::vector<GeneratedTree> TreeVariantCache::generate(const std::vector<const TreeVariantSpec*>& specs) const {
  std::vector<GeneratedTree> trees(specs.size());
  TreeMemo* memo = b_.options().tree_memo.get();
  tbb::parallel_for(size_t{0}, specs.size(), [&](size_t i) {
    const TreeVariantSpec& s = *specs[i];
    const std::string key = memo ? TreeMemo::key(s.file.string(), s.seed, s.options, s.with_leaves) : std::string();
    if (memo) {
      if (std::optional<GeneratedTree> known = memo->find(key)) {
        trees[i] = std::move(*known);
        return;
      }
    }
    trees[i] = generate_tree(*s.species, s.seed, s.options, s.with_leaves);
    if (memo && trees[i].error.empty()) memo->remember(key, trees[i]);
  });
  return trees;
}

void TreeVariantCache::add(const TreeVariantSpec& spec, GeneratedTree& tree, bool defer_full) {
  if (has(spec.key)) return;
  Entry e;
  e.levels.resize(kLodLevelR2.size());
  if (b_.lod.enabled) e.bounds = bounds_of(tree.mesh);
  if (defer_full) {
    e.source = std::move(tree);
  } else {
    if (b_.lod.enabled) e.source = lod_source(tree);
    e.levels[0] = add_full_prototypes(spec, tree);
  }
  tree = GeneratedTree{};
  entries_.emplace(spec.key, std::move(e));
}

std::vector<const std::vector<uint32_t>*> TreeVariantCache::draw(const std::vector<const TreeVariantSpec*>& specs,
                                                                 const std::vector<uint32_t>& variant,
                                                                 const std::function<Mat4(size_t)>& world_from_object) {
  // The distinct entries, in first-listed order.
  std::vector<const TreeVariantSpec*> variants;
  std::vector<size_t> slot(specs.size());
  std::map<std::string, size_t> slot_of_key;
  for (size_t i = 0; i < specs.size(); ++i) {
    auto [it, added] = slot_of_key.emplace(specs[i]->key, variants.size());
    if (added) variants.push_back(specs[i]);
    slot[i] = it->second;
  }
  std::vector<Entry*> entry(variants.size());
  for (size_t v = 0; v < variants.size(); ++v) entry[v] = &entries_.at(variants[v]->key);
  const size_t levels = kLodLevelR2.size();
  const Scene& scene = b_.scene();
  const RenderSettings& render = b_.file().render;
  std::vector<uint8_t> level(variant.size(), 0), used(variants.size() * levels, 0);
  for (size_t i = 0; i < variant.size(); ++i) {
    const size_t v = slot[variant[i]];
    if (b_.lod.enabled)
      level[i] = static_cast<uint8_t>(instance_lod_level(b_.lod, scene.camera, render.width, render.height,
                                                         transformed(entry[v]->bounds, world_from_object(i))));
    used[v * levels + level[i]] = 1;
  }
  for (size_t v = 0; v < variants.size(); ++v)
    for (size_t k = 0; k < levels; ++k)
      if (entry[v]->levels[k]) used[v * levels + k] = 0;
  make_levels(variants, used);
  for (Entry* e : entry) e->source.reset();
  std::vector<const std::vector<uint32_t>*> out(variant.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = &*entry[slot[variant[i]]]->levels[level[i]];
  return out;
}

// The trees the levels in `used` are made from, by variant: each entry's kept source, else the tree
// generated again (pure, so the same tree).
std::vector<GeneratedTree> TreeVariantCache::take_sources(const std::vector<const TreeVariantSpec*>& variants,
                                                          const std::vector<uint8_t>& used) {
  const size_t levels = kLodLevelR2.size();
  std::vector<GeneratedTree> sources(variants.size());
  std::vector<const TreeVariantSpec*> again;
  std::vector<size_t> again_index;
  for (size_t v = 0; v < variants.size(); ++v) {
    const auto first = used.begin() + static_cast<ptrdiff_t>(v * levels);
    if (std::find(first, first + static_cast<ptrdiff_t>(levels), 1) == first + static_cast<ptrdiff_t>(levels)) continue;
    Entry& e = entries_.at(variants[v]->key);
    if (e.source) {
      sources[v] = std::move(*e.source);
      e.source.reset();
    } else {
      again.push_back(variants[v]);
      again_index.push_back(v);
    }
  }
  std::vector<GeneratedTree> made = generate(again);
  for (size_t i = 0; i < again.size(); ++i) {
    if (!made[i].error.empty()) again[i]->table->fail(again[i]->file.string() + ": " + made[i].error);
    sources[again_index[i]] = std::move(made[i]);
  }
  return sources;
}

void TreeVariantCache::make_levels(const std::vector<const TreeVariantSpec*>& variants,
                                   const std::vector<uint8_t>& used) {
  const size_t levels = kLodLevelR2.size();
  std::vector<GeneratedTree> sources = take_sources(variants, used);
  std::vector<LodJob> jobs = build_lod_levels(used, sources);
  size_t job = 0;
  for (size_t v = 0; v < variants.size(); ++v) {
    const TreeVariantSpec& spec = *variants[v];
    Entry& e = entries_.at(spec.key);
    if (used[v * levels]) e.levels[0] = add_full_prototypes(spec, sources[v]);
    for (; job < jobs.size() && jobs[job].variant == v; ++job)
      e.levels[jobs[job].level] = add_level_prototypes(spec, jobs[job].lod);
    sources[v] = GeneratedTree{};
  }
}

// Dead branches' bark: the spec's `dead_bark`, else a copy of its bark with the reflectance scaled
// by kDeadBarkReflectanceScale (docs/scene_format.md), made once per bark material. Without dead
// branches (`needed` false) the bark itself, and `dead_bark` is not looked up.
uint32_t TreeVariantCache::dead_bark(const TreeVariantSpec& spec, bool needed) {
  const uint32_t bark = spec.materials[0];
  if (!needed) return bark;
  if (spec.table->has("dead_bark")) return b_.material_ref(*spec.table, "dead_bark");
  const std::string name = b_.scene().material_names[bark] + " (dead, reflectance x0.5)";
  if (const std::optional<uint32_t> found = b_.find_material(name)) return *found;
  return b_.add_material(name, scaled_reflectance(b_.scene().materials[bark], kDeadBarkReflectanceScale));
}

// The prototypes of a generated tree: stems with the first leaf material slot, one more per further
// slot with leaves, and the dead branches. `tree` is consumed.
std::vector<uint32_t> TreeVariantCache::add_full_prototypes(const TreeVariantSpec& spec, GeneratedTree& tree) {
  const std::vector<uint32_t>& materials = spec.materials;
  std::vector<uint32_t> protos;
  Prototype p;
  p.name = spec.name;
  p.triangles = std::move(tree.mesh.stems);
  p.triangle_material = materials[0];
  for (size_t slot = 0; slot + 1 < materials.size(); ++slot) {
    LeafQuads quads = leaves_in_slot(tree.mesh.leaves, tree.model.leaves, slot, materials.size() - 2);
    if (slot > 0 && quads.size() == 0) continue;
    p.leaves = std::move(quads);
    p.leaf_material = materials[slot + 1];
    protos.push_back(b_.scene().add_prototype(std::move(p)));
    p = Prototype{};
    p.name = fmt::format("{} (leaf material {})", spec.name, slot + 1);
  }
  if (!tree.mesh.dead_stems.triangles.empty()) {
    Prototype dead;
    dead.name = spec.name + " (dead branches)";
    dead.triangles = std::move(tree.mesh.dead_stems);
    dead.triangle_material = dead_bark(spec, true);
    protos.push_back(b_.scene().add_prototype(std::move(dead)));
  }
  tree.model = TreeModel{};
  return protos;
}

// The prototypes of one level of detail (lod_prototypes), in the layout of add_full_prototypes.
std::vector<uint32_t> TreeVariantCache::add_level_prototypes(const TreeVariantSpec& spec, TreeLod& level) {
  const bool dead = !level.mesh.dead_stems.triangles.empty() || level.dead_lines.size() > 0;
  const uint32_t dead_material = dead_bark(spec, dead);
  std::vector<uint32_t> ids;
  for (Prototype& p : lod_prototypes(spec.name, level, spec.materials, dead_material))
    ids.push_back(b_.scene().add_prototype(std::move(p)));
  return ids;
}

const std::vector<uint32_t>* TreeVariantCache::find(const std::string& key) const {
  auto it = other_.find(key);
  return it == other_.end() ? nullptr : &it->second;
}

const std::vector<uint32_t>& TreeVariantCache::insert(const std::string& key, std::vector<uint32_t> prototypes) {
  return other_.emplace(key, std::move(prototypes)).first->second;
}

}  // namespace sylva
