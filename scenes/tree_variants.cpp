#include "scenes/tree_variants.h"

#include "core/error.h"
#include "geometry/trees/lod.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include <fmt/core.h>

namespace sylva {

GeneratedTree generate_tree(const Species& species, uint64_t seed, const TreeOptions& options, bool with_leaves) {
  GeneratedTree out;
  try {
    out.model = make_species_model(species, seed, options);
    out.mesh_options.quality = options.quality;
    out.mesh_options.split_dead_stems = true;
    out.mesh_options.leaves = with_leaves;
    out.mesh = mesh_species_model(species, out.model, out.mesh_options);
  } catch (const Error& e) {
    out.error = e.what();
  }
  return out;
}

std::string TreeMemo::key(const std::string& species_file, uint64_t seed, const TreeOptions& options,
                          bool with_leaves) {
  return fmt::format("{}|{}|{}|{}|{}|{}|{}|{}", species_file, seed, options.quality, options.time_s, options.wind_speed,
                     options.wind_gust, options.years, with_leaves);
}

std::optional<GeneratedTree> TreeMemo::find(const std::string& key) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto it = trees_.find(key);
  if (it == trees_.end()) return std::nullopt;
  it->second.scene = scene_;
  ++reused_;
  return it->second.tree;
}

void TreeMemo::remember(const std::string& key, const GeneratedTree& tree) {
  const std::lock_guard<std::mutex> lock(mutex_);
  trees_.insert_or_assign(key, Entry{tree, scene_});
  ++generated_;
}

void TreeMemo::next_scene() {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::erase_if(trees_, [&](const auto& entry) { return entry.second.scene < scene_; });
  ++scene_;
}

size_t TreeMemo::size() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return trees_.size();
}

// What make_tree_lod reads of a generated tree: the model, the leaf quads and the mesh options
// (not the bark tubes, which it meshes again from the model).
GeneratedTree lod_source(const GeneratedTree& tree) {
  GeneratedTree out;
  out.model = tree.model;
  out.mesh.leaves = tree.mesh.leaves;
  out.mesh_options = tree.mesh_options;
  return out;
}

// `used[v · levels + k]` marks level k of variant v as drawn by some instance: the jobs for
// k ≥ 1, in variant then level order, built in parallel from `sources` (results by index, so
// independent of the thread count).
std::vector<LodJob> build_lod_levels(const std::vector<uint8_t>& used, const std::vector<GeneratedTree>& sources) {
  const size_t levels = kLodLevelR2.size();
  std::vector<LodJob> jobs;
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i] && i % levels != 0) jobs.push_back(LodJob{i / levels, i % levels, {}});
  tbb::parallel_for(size_t{0}, jobs.size(), [&](size_t i) {
    const GeneratedTree& g = sources[jobs[i].variant];
    jobs[i].lod = make_tree_lod(g.model, g.mesh, g.mesh_options, kLodLevelR2[jobs[i].level]);
  });
  return jobs;
}

// The leaf quads of material slot `slot` (the last slot also takes every slot beyond it), in
// order, with their stem ids. `quads` were meshed from `leaves`, one quad per leaf.
LeafQuads leaves_in_slot(const LeafQuads& quads, const TreeLeaves& leaves, size_t slot, size_t last) {
  LeafQuads out;
  for (size_t i = 0; i < quads.size(); ++i) {
    const size_t s = std::min<size_t>(leaves.material_of(i), last);
    if (s != slot) continue;
    out.corners.insert(out.corners.end(), quads.corners.begin() + static_cast<ptrdiff_t>(4 * i),
                       quads.corners.begin() + static_cast<ptrdiff_t>(4 * i + 4));
    out.shapes.push_back(quads.shapes[i]);
    if (!quads.stem.empty()) out.stem.push_back(quads.stem[i]);
  }
  return out;
}

}  // namespace sylva
