#pragma once
// The scene builder: what the section families (scenes/sections/*.h) read and add to while a scene
// file is assembled. Each family reads and validates its own keys (pbrt-v4's `Create(parameters,
// loc)`) and adds its materials, prototypes and instances here; the builder holds the tables they
// share (materials by name, the class and variant tables, species files read, the tree variants)
// and what one section leaves for a later one (the terrain, the grass types, [lod]).
// docs/design.md §3, "Scene sections".

#include "core/params.h"
#include "geometry/ground.h"
#include "geometry/terrain.h"
#include "scenes/scene_file.h"
#include "scenes/species.h"
#include "scenes/tree_lod.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace sylva {

class TreeVariantCache;

class SceneBuilder {
 public:
  SceneBuilder(const Params& root, const SceneOptions& options);
  ~SceneBuilder();
  SceneBuilder(const SceneBuilder&) = delete;
  SceneBuilder& operator=(const SceneBuilder&) = delete;

  const Params& root() const { return root_; }
  const SceneOptions& options() const { return options_; }
  SceneFile& file() { return out_; }
  const SceneFile& file() const { return out_; }
  Scene& scene() { return out_.scene; }
  const Scene& scene() const { return out_.scene; }

  // Materials by name ([materials.NAME], then those made for trees: template colours, darker bark).
  // add_material adds one under a new name (the caller checks that the name is new).
  uint32_t add_material(const std::string& name, Material material);
  // The id of a material made before under `name`, if any.
  std::optional<uint32_t> find_material(const std::string& name) const;
  // The material the string `key` of `t` names; fails at it ("unknown material ...") otherwise.
  uint32_t material_ref(const Params& t, const char* key) const;

  // The `id.class` of a name (a species, a target label, a [[meshes]] `class`): class_id_of(name),
  // entered in the class table the first time (docs/scene_format.md, "Label AOVs"). If another name
  // of the scene has the same id, fails at `at`'s `key` (`file:line: ...`, ParseError).
  uint32_t class_of(const std::string& name, const Params& at, std::string_view key);
  // The `id.variant` of a generated tree or target mesh, by its key (a new row the first time).
  uint32_t variant_of(const std::string& key, VariantInfo info);

  // A species file, read and parsed once per build; its text (and a TREE-MAKER template's) enters
  // the dependency hash and its warnings the scene's.
  const Species& load_species_once(const std::filesystem::path& file);
  uint64_t dependency_hash() const { return dependency_hash_; }
  const std::map<std::string, Species>& species() const { return species_; }

  // The tree variants of [[trees]], [[placements]] and [vegetation] and their prototypes
  // (scenes/sections/tree_variant_cache.h).
  TreeVariantCache& tree_variants() { return *tree_variants_; }

  // Where a table's copies go: its transform (translate, rotate, scale), each of its `instances`
  // (or itself), each tile of a `tile`d plot, each offset in `at`, in that nesting order.
  struct Placed {
    Mat4 world_from_object;
    uint32_t object_id;
  };
  std::vector<Placed> placements(const Params& t, const std::vector<Vec3>& at = {Vec3(0.0f)}) const;
  // Places an instance of `proto` at each of placements(t, at), labelled `class_id`, `variant_id`.
  void place(const Params& t, uint32_t proto, uint32_t class_id = kClassMesh, uint32_t variant_id = 0,
             const std::vector<Vec3>& at = {Vec3(0.0f)});

  // Instances [begin, end) hold provisional object ids 1, 2, ... ([[placements]], [[targets]]);
  // finish() moves them above every id the file gives explicitly, in the order recorded.
  void add_automatic_ids(size_t begin, size_t end) { automatic_ranges_.emplace_back(begin, end); }
  // Assigns the automatic object ids and returns the scene file.
  SceneFile finish();

  // What one section leaves for later ones.
  // [[meshes]]: the classes of the meshes placed (kClassMesh or a mesh's `class`), which [[targets]]
  // snap onto along with the terrain.
  std::set<uint32_t> mesh_classes{kClassMesh};
  // [camera] above_terrain: position and target z are heights above the [terrain].
  bool camera_above_terrain = false;
  // [lod]: Weber & Penn §5 level of detail for [[trees]], [[placements]] and [vegetation].
  LodSettings lod;
  // [terrain]: the height field and the extent a feature map covers.
  std::optional<HeightField> terrain;
  Vec2 extent_min{0.0f}, extent_max{0.0f};
  // [[grass]]: the patch prototype and size of each grass type, in feature-map order.
  struct GrassType {
    uint32_t prototype = 0;
    float patch_size_m = 0.0f;
  };
  std::vector<GrassType> grass;

 private:
  const Params& root_;
  SceneOptions options_;
  SceneFile out_;
  std::map<std::string, uint32_t> material_ids_;
  std::map<std::string, Species> species_;
  std::map<std::string, uint32_t> variant_ids_;
  std::vector<std::pair<size_t, size_t>> automatic_ranges_;
  uint64_t dependency_hash_ = 0;
  std::unique_ptr<TreeVariantCache> tree_variants_;
};

// The class id of a name, the same in every scene and study: the built-in classes' own ids
// (kClassSky "sky", kClassTerrain "terrain", kClassGrass "grass", kClassMesh "mesh"), any other name
// kFirstNamedClass + FNV-1a 64 of its UTF-8 bytes modulo (kMaxClassId − kFirstNamedClass).
uint32_t class_id_of(std::string_view name);

// translate = [x,y,z], rotate = [rx,ry,rz] degrees (applied X, then Y, then Z), scale = s or [sx,sy,sz].
Mat4 read_transform(const Params& t);

// `key = x` or `key = [lo, hi]` (lo <= hi) within [lo_limit, hi_limit]; `fallback` when absent.
Vec2 read_range(const Params& t, const char* key, Vec2 fallback, double lo_limit, double hi_limit);

// Hash of a text as the scene hash chains it.
uint64_t hash_text(std::string_view text);

}  // namespace sylva
