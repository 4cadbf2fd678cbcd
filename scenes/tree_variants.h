#pragma once
// Generating tree variants for scene assembly: a tree made from a species and seed (pure, so
// variants are generated in parallel), its levels of detail (built in parallel, results by index
// so independent of the thread count) and its leaf quads split by material slot.

#include "geometry/mesh.h"
#include "geometry/trees/lod.h"
#include "geometry/trees/tree_mesher.h"
#include "scenes/species.h"

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace sylva {

// A tree made from a species and seed (TreeModel and mesh), or the message of why it could not
// be. `mesh_options` are those it was meshed with (for its levels of detail).
struct GeneratedTree {
  TreeModel model;
  TreeMesh mesh;
  TreeMeshOptions mesh_options;
  std::string error;
};
// Never throws: a generator's Error becomes `error`.
GeneratedTree generate_tree(const Species& species, uint64_t seed, const TreeOptions& options, bool with_leaves);

// Trees generated for earlier scenes of one process — the frames of a study (pipeline/study.h) —
// kept to be copied into later scenes instead of generated again. Generation is a pure function
// of (species file, seed, options, leaves), so a scene is the same bits with or without it; the
// species files are assumed unchanged while it lives. Memory stays bounded: next_scene() forgets
// every tree the previous scene did not use. Thread-safe.
class TreeMemo {
 public:
  // The key of generate_tree's inputs (the species by its file).
  static std::string key(const std::string& species_file, uint64_t seed, const TreeOptions& options, bool with_leaves);
  // A copy of the tree remembered under `key`, if any (and marks it used by this scene).
  std::optional<GeneratedTree> find(const std::string& key);
  void remember(const std::string& key, const GeneratedTree& tree);
  // Starts the next scene: trees neither found nor remembered since the last call are dropped.
  void next_scene();
  size_t size() const;
  uint64_t generated() const { return generated_; }  // trees remembered so far
  uint64_t reused() const { return reused_; }        // trees found so far

 private:
  struct Entry {
    GeneratedTree tree;
    uint64_t scene = 0;  // the last scene that used it
  };
  mutable std::mutex mutex_;
  std::map<std::string, Entry> trees_;
  uint64_t scene_ = 0;
  uint64_t generated_ = 0, reused_ = 0;
};

// What make_tree_lod reads of a generated tree: the model, the leaf quads and the mesh options
// (not the bark tubes, which it meshes again from the model).
GeneratedTree lod_source(const GeneratedTree& tree);

// Levels of detail to build: level `level` >= 1 of variant `variant`, from the variant's tree.
struct LodJob {
  size_t variant = 0;
  size_t level = 0;
  TreeLod lod;
};
// `used[v * levels + k]` marks level k of variant v as drawn by some instance: the jobs for
// k >= 1, in variant then level order, built in parallel from `sources`.
std::vector<LodJob> build_lod_levels(const std::vector<uint8_t>& used, const std::vector<GeneratedTree>& sources);

// The leaf quads of material slot `slot` (the last slot also takes every slot beyond it), in
// order, with their stem ids. `quads` were meshed from `leaves`, one quad per leaf.
LeafQuads leaves_in_slot(const LeafQuads& quads, const TreeLeaves& leaves, size_t slot, size_t last);

}  // namespace sylva
