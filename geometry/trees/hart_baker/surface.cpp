// The Hart–Baker surface as one mesh: the shared mesher's tubes, the blended joints (§5.2) put into
// them, and the bark (§5.4) on top.

#include "geometry/trees/hart_baker/surface_detail.h"

#include <algorithm>
#include <limits>

namespace sylva {

namespace surface_detail {
namespace {

// Where the shared mesher put a stem's tube in its stems mesh (make_tree_mesh's layout: a base
// cap centre, `rings` rings of m + 1 vertices, a tip vertex; m base-cap triangles, 2m per band,
// m at the tip).
struct TubeLayout {
  uint32_t first_vertex = 0, first_triangle = 0, triangles = 0, m = 0, rings = 0;
};

std::vector<TubeLayout> tube_layout(const TreeModel& model, const TreeMeshOptions& options) {
  std::vector<TubeLayout> layout(model.stems.size());
  uint32_t vertices = 0, triangles = 0;
  for (size_t s = 0; s < model.stems.size(); ++s) {
    const uint32_t count = model.stems.section_count[s];
    if (count < 2 || (options.split_dead_stems && model.stems.is_dead(s))) continue;
    TubeLayout& l = layout[s];
    l.m = static_cast<uint32_t>(radial_segments_for_level(options, model.stems.level[s], model.stems.lobes[s]));
    const uint32_t last = model.stems.first_section[s] + count - 1;
    l.rings = model.sections.radius_m[last] <= 1e-7f ? count - 1 : count;
    l.first_vertex = vertices;
    l.first_triangle = triangles;
    l.triangles = l.m + (l.rings - 1) * 2 * l.m + l.m;
    vertices += 2 + l.rings * (l.m + 1);
    triangles += l.triangles;
  }
  return layout;
}

// Puts the joints into the tubes' mesh: stitched joints replace the tubes between their node and
// their rings and are zipped to the rings; the others are added closed.
void add_joints(TriangleMesh& stems, const TreeModel& ringed, const std::vector<JointPlan>& plans,
                const TreeMeshOptions& options) {
  const std::vector<TubeLayout> layout = tube_layout(ringed, options);
  std::vector<uint8_t> dropped(stems.triangles.size(), 0);
  auto drop = [&](uint32_t from, uint32_t to) { std::fill(dropped.begin() + from, dropped.begin() + to, 1); };
  for (const JointPlan& plan : plans) {
    const uint32_t offset = static_cast<uint32_t>(stems.positions.size());
    append_mesh(stems, plan.mesh);
    if (!plan.stitched) continue;
    for (const int32_t s : plan.inside) {
      const TubeLayout& l = layout[static_cast<size_t>(s)];
      drop(l.first_triangle, l.first_triangle + l.triangles);
    }
    for (const JointCut& cut : plan.cuts) {
      const size_t s = static_cast<size_t>(cut.stem);
      const TubeLayout& l = layout[s];
      const uint32_t first = ringed.stems.first_section[s];
      // with_rings put a section at exactly this arc (or the walk snapped to one).
      uint32_t k = 0;
      while (k + 1 < ringed.stems.section_count[s] && ringed.sections.arc_m[first + k] != cut.ring_arc_m) ++k;
      const uint32_t band = l.first_triangle + l.m + 2 * l.m * k;
      if (cut.toward_tip)
        drop(l.first_triangle, band);
      else
        drop(band, l.first_triangle + l.triangles);
      zipper(stems, cut, offset, l.first_vertex + 1 + k * (l.m + 1), l.m);
    }
  }
  // Drop the trimmed triangles and the vertices nothing uses any more.
  std::vector<glm::uvec3> kept;
  kept.reserve(stems.triangles.size());
  for (size_t t = 0; t < stems.triangles.size(); ++t)
    if (t >= dropped.size() || !dropped[t]) kept.push_back(stems.triangles[t]);
  std::vector<uint32_t> index(stems.positions.size(), std::numeric_limits<uint32_t>::max());
  for (const glm::uvec3& t : kept)
    for (int e = 0; e < 3; ++e) index[t[e]] = 0;
  uint32_t used = 0;
  for (size_t v = 0; v < index.size(); ++v)
    if (index[v] == 0) {
      index[v] = used;
      stems.positions[used] = stems.positions[v];
      if (!stems.normals.empty()) stems.normals[used] = stems.normals[v];
      if (!stems.uvs.empty()) stems.uvs[used] = stems.uvs[v];
      ++used;
    }
  stems.positions.resize(used);
  if (!stems.normals.empty()) stems.normals.resize(used);
  if (!stems.uvs.empty()) stems.uvs.resize(used);
  for (glm::uvec3& t : kept) t = glm::uvec3(index[t.x], index[t.y], index[t.z]);
  stems.triangles = std::move(kept);
}

}  // namespace
}  // namespace surface_detail

TreeMesh make_hart_baker_mesh(const TreeModel& model, const HartBakerParams& params, const TreeMeshOptions& options) {
  using namespace surface_detail;  // the internals (surface_detail.h)
  if (!params.surface.blend) {
    TreeMesh mesh = make_tree_mesh(model, options);
    append_mesh(mesh.stems, hart_baker_bark(model, params));
    return mesh;
  }
  const HartBakerJoints joints = plan_hart_baker_joints(model, params.surface, options);
  TreeMesh mesh = make_tree_mesh(joints.ringed, options);
  add_joints(mesh.stems, joints.ringed, joints.plans, options);
  append_mesh(mesh.stems, hart_baker_bark(model, params, joints.plans));
  return mesh;
}

}  // namespace sylva
