#pragma once
// One tree variant, as [[trees]], [[placements]] and [vegetation] specify it, and one cache of the
// prototypes made for it at each level of detail (Weber & Penn §5, docs/lod.md). A variant is a
// species file and seed with its options and materials; variants with the same key share their
// prototypes, each level made once, when some copy first draws it. Generation and the levels run
// in parallel with results by index, so the scene does not depend on the thread count.

#include "core/params.h"
#include "scenes/sections/scene_builder.h"
#include "scenes/tree_variants.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace sylva {

struct TreeVariantSpec {
  const Params* table = nullptr;  // where it is named: its `dead_bark` is read from it
  const Species* species = nullptr;
  std::filesystem::path file;  // the species file, as resolved
  uint64_t seed = 1;
  TreeOptions options;
  bool with_leaves = true;
  std::vector<uint32_t> materials;  // bark, then one per leaf material slot (tree_materials)
  std::string name;                 // of the prototypes it makes
  // The cache key: variants with equal keys share prototypes (tree_variant_key; [vegetation]
  // gives each of its variants a key of its own).
  std::string key;
};

// The key of a variant: species file, seed, options, leaves, materials, `dead_bark` of `t`.
std::string tree_variant_key(const TreeVariantSpec& spec, const Params& t);

// A tree's materials: bark, then one per leaf material slot. Named ones come from the scene (keys
// bark, leaf, flower of `t`); a TREE-MAKER species fills what the scene leaves out with its
// template's colours (docs/treemaker.md: Smits up-sampling; bark diffuse, elements opaque
// two-sided leaves). Other models need `bark` and `leaf`; a tree without leaves may leave out
// `leaf`.
std::vector<uint32_t> tree_materials(const Params& t, const Species& species, bool with_leaves, SceneBuilder& b);

class TreeVariantCache {
 public:
  explicit TreeVariantCache(SceneBuilder& builder) : b_(builder) {}

  bool has(const std::string& key) const { return entries_.count(key) > 0; }

  // The trees of `specs`, generated in parallel (a generator's failure is the tree's `error`), or
  // copied from the scene options' TreeMemo when an earlier scene made them.
  std::vector<GeneratedTree> generate(const std::vector<const TreeVariantSpec*>& specs) const;

  // Adds a variant made from `tree` (consumed) unless its key is cached: its full prototypes now,
  // or with `defer_full` (under [lod]) only when a copy first draws the full level.
  void add(const TreeVariantSpec& spec, GeneratedTree& tree, bool defer_full);

  // The prototypes each copy draws: copy i is of variant specs[variant[i]] (added before) placed by
  // world_from_object(i), at its level of detail under [lod] (level 0 without; world_from_object
  // is then not called). Levels no copy drew before are made (in parallel) and added in variant
  // then level order, named after and with the `dead_bark` of the first spec of their key.
  std::vector<const std::vector<uint32_t>*> draw(const std::vector<const TreeVariantSpec*>& specs,
                                                 const std::vector<uint32_t>& variant,
                                                 const std::function<Mat4(size_t)>& world_from_object);

  // Prototypes cached under a key of the caller's (Fournier–Grindal solids), or nullptr.
  const std::vector<uint32_t>* find(const std::string& key) const;
  const std::vector<uint32_t>& insert(const std::string& key, std::vector<uint32_t> prototypes);

 private:
  struct Entry {
    std::vector<std::optional<std::vector<uint32_t>>> levels;  // prototypes per level, once made
    Bounds3 bounds;                                            // of the full tree (object space)
    // Under [lod], until first drawn: what the levels are made from (the whole tree when its full
    // level is deferred).
    std::optional<GeneratedTree> source;
  };
  std::vector<uint32_t> add_full_prototypes(const TreeVariantSpec& spec, GeneratedTree& tree);
  std::vector<uint32_t> add_level_prototypes(const TreeVariantSpec& spec, TreeLod& level);
  uint32_t dead_bark(const TreeVariantSpec& spec, bool needed);
  void make_levels(const std::vector<const TreeVariantSpec*>& variants, const std::vector<uint8_t>& used);
  std::vector<GeneratedTree> take_sources(const std::vector<const TreeVariantSpec*>& variants,
                                          const std::vector<uint8_t>& used);

  SceneBuilder& b_;
  std::map<std::string, Entry> entries_;
  std::map<std::string, std::vector<uint32_t>> other_;  // find / insert
};

}  // namespace sylva
