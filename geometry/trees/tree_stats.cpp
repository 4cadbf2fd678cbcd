#include "geometry/trees/tree_stats.h"

#include "core/hash.h"

#include <fmt/core.h>

namespace sylva {

namespace {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(c));
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string json_ints(const std::vector<int>& v) {
  std::string out = "[";
  for (size_t i = 0; i < v.size(); ++i) out += fmt::format("{}{}", i ? ", " : "", v[i]);
  return out + "]";
}

}  // namespace

uint64_t hash_tree_mesh(const TreeMesh& mesh) {
  WordHash64 h;
  h.add_vector(mesh.stems.positions);
  h.add_vector(mesh.stems.normals);
  h.add_vector(mesh.stems.uvs);
  h.add_vector(mesh.stems.triangles);
  // Only a split mesh hashes its dead stems, so unsplit meshes keep their hashes.
  if (!mesh.dead_stems.triangles.empty()) {
    h.add_vector(mesh.dead_stems.positions);
    h.add_vector(mesh.dead_stems.normals);
    h.add_vector(mesh.dead_stems.uvs);
    h.add_vector(mesh.dead_stems.triangles);
  }
  h.add_vector(mesh.leaves.corners);
  h.add_vector(mesh.leaves.shapes);
  return h.value();
}

std::vector<int> count_stems_per_level(const TreeModel& model) {
  std::vector<int> n;
  for (size_t i = 0; i < model.stems.size(); ++i) {
    const size_t level = model.stems.level[i];
    if (n.size() <= level) n.resize(level + 1, 0);
    ++n[level];
  }
  return n;
}

TreeStats compute_tree_stats(const TreeModel& model, const TreeMesh& mesh) {
  TreeStats s;
  for (size_t i = 0; i < model.stems.size(); ++i) {
    const size_t level = model.stems.level[i];
    if (s.stems_per_level.size() <= level) {
      s.stems_per_level.resize(level + 1, 0);
      s.clones_per_level.resize(level + 1, 0);
    }
    ++s.stems_per_level[level];
    if (model.stems.is_clone(i)) ++s.clones_per_level[level];
  }
  s.leaves = static_cast<int>(model.leaves.size());
  s.vertices = mesh.stems.positions.size() + mesh.dead_stems.positions.size();
  s.triangles = mesh.stems.triangles.size() + mesh.dead_stems.triangles.size();
  s.quads = mesh.leaves.size();
  s.bounds = bounds_of(mesh);
  s.height_m = s.bounds.empty() ? 0.0f : s.bounds.hi.z - s.bounds.lo.z;
  for (size_t i = 0; i < mesh.leaves.size(); ++i) s.leaf_area_m2 += leaf_quad_area(mesh.leaves, i);
  s.mesh_hash = hash_tree_mesh(mesh);
  return s;
}

std::string tree_stats_json(const TreeStats& s, const std::string& species, uint64_t seed,
                            std::optional<double> generation_ms) {
  std::string out = "{\n";
  out += fmt::format("  \"species\": {},\n", json_string(species));
  out += fmt::format("  \"seed\": {},\n", seed);
  out += fmt::format("  \"stems_per_level\": {},\n", json_ints(s.stems_per_level));
  out += fmt::format("  \"clones_per_level\": {},\n", json_ints(s.clones_per_level));
  out += fmt::format("  \"leaves\": {},\n", s.leaves);
  out += fmt::format("  \"vertices\": {},\n", s.vertices);
  out += fmt::format("  \"triangles\": {},\n", s.triangles);
  out += fmt::format("  \"quads\": {},\n", s.quads);
  out += fmt::format("  \"height_m\": {:.6f},\n", s.height_m);
  // An empty tree has no bounds: null, not the infinities of an empty box (not valid JSON).
  if (s.bounds.empty()) {
    out += "  \"bbox_min\": null,\n  \"bbox_max\": null,\n";
  } else {
    out += fmt::format("  \"bbox_min\": [{:.6f}, {:.6f}, {:.6f}],\n", s.bounds.lo.x, s.bounds.lo.y, s.bounds.lo.z);
    out += fmt::format("  \"bbox_max\": [{:.6f}, {:.6f}, {:.6f}],\n", s.bounds.hi.x, s.bounds.hi.y, s.bounds.hi.z);
  }
  out += fmt::format("  \"leaf_area_m2\": {:.6f},\n", s.leaf_area_m2);
  if (generation_ms) out += fmt::format("  \"generation_ms\": {:.3f},\n", *generation_ms);
  out += fmt::format("  \"mesh_hash\": \"{}\"\n", hex64(s.mesh_hash));
  return out + "}\n";
}

}  // namespace sylva
