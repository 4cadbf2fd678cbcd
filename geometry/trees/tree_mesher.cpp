#include "geometry/trees/tree_mesher.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sylva {

namespace {

// Radius below which a stem end is closed by a single tip vertex.
constexpr float kTipRadius = 1e-7f;

Vec3 safe_normalize(const Vec3& v, const Vec3& fallback) {
  const float l = glm::length(v);
  return l > 1e-12f ? v / l : fallback;
}

// cos, sin and the lobe factor around a ring of m vertices, kept while consecutive stems share them.
struct RingTrig {
  int m = -1, lobes = -1;
  float lobe_depth = 0.0f;
  std::vector<float> cos_t, sin_t, lobe;
};

}  // namespace

int radial_segments_for_level(const TreeMeshOptions& options, int level, int lobes) {
  const int base = options.radial_segments[static_cast<size_t>(std::clamp(level, 0, 3))];
  int n = std::max(3, static_cast<int>(std::lround(static_cast<float>(base) * options.quality)));
  if (lobes > 0) n = std::max(n, 4 * lobes);
  return n;
}

namespace {

// Reserves the stems mesh from a count of rings and segments.
void reserve_stems(TriangleMesh& live, const TreeStems& stems, const TreeMeshOptions& options) {
  size_t vertex_estimate = 0, triangle_estimate = 0;
  for (size_t s = 0; s < stems.size(); ++s) {
    const size_t m = static_cast<size_t>(radial_segments_for_level(options, stems.level[s], stems.lobes[s]));
    vertex_estimate += stems.section_count[s] * (m + 1) + 2;
    triangle_estimate += stems.section_count[s] * 2 * m;
  }
  live.positions.reserve(vertex_estimate);
  live.normals.reserve(vertex_estimate);
  live.uvs.reserve(vertex_estimate);
  live.triangles.reserve(triangle_estimate);
}

// Recomputes the ring's table for m vertices and the lobes, unless it already holds them.
void update_ring_trig(RingTrig& trig, int m, int lobes, float lobe_depth) {
  if (m == trig.m && lobes == trig.lobes && lobe_depth == trig.lobe_depth) return;
  trig.m = m;
  trig.lobes = lobes;
  trig.lobe_depth = lobe_depth;
  trig.cos_t.resize(static_cast<size_t>(m) + 1);
  trig.sin_t.resize(static_cast<size_t>(m) + 1);
  trig.lobe.resize(static_cast<size_t>(m) + 1);
  for (int j = 0; j <= m; ++j) {
    const float theta = kTwoPi * static_cast<float>(j % m) / static_cast<float>(m);
    trig.cos_t[static_cast<size_t>(j)] = std::cos(theta);
    trig.sin_t[static_cast<size_t>(j)] = std::sin(theta);
    trig.lobe[static_cast<size_t>(j)] =
        lobes > 0 ? 1.0f + lobe_depth * std::sin(static_cast<float>(lobes) * theta) : 1.0f;
  }
}

// Ring axes: the first ring follows the stem's first frame, the others bisect the segments.
void ring_tangents(const StemSections& sec, uint32_t first, uint32_t count, std::vector<Vec3>& tangents) {
  tangents.resize(count);
  const Vec3 z0 = sec.frames[first].z;
  tangents[0] = z0;
  for (uint32_t k = 1; k < count; ++k) {
    const Vec3 in = safe_normalize(sec.positions[first + k] - sec.positions[first + k - 1], sec.frames[first + k].z);
    if (k + 1 < count) {
      const Vec3 next = safe_normalize(sec.positions[first + k + 1] - sec.positions[first + k], in);
      tangents[k] = safe_normalize(in + next, in);
    } else {
      tangents[k] = in;
    }
  }
}

// One stem's tube: where its sections are, how many rings of m vertices it has, their axes, and
// the v texture scale.
struct Tube {
  uint32_t first, count, rings;
  int m;
  float v_scale;
};

// The tube's rings of m + 1 vertices (the last repeating the first, for the texture's seam), the
// reference axis transported from ring to ring and the normals tilted by the taper.
void add_rings(TriangleMesh& out, const StemSections& sec, const Tube& tube, const RingTrig& trig,
               const std::vector<Vec3>& tangents) {
  const uint32_t first = tube.first, count = tube.count;
  const int m = tube.m;
  Vec3 ex = sec.frames[first].x;
  for (uint32_t k = 0; k < tube.rings; ++k) {
    const uint32_t i = first + k;
    const Vec3 t = tangents[k];
    // Parallel transport of the ring's reference axis.
    ex = safe_normalize(ex - t * glm::dot(ex, t), Frame::from_z(t).x);
    const Vec3 ey = glm::cross(t, ex);
    const float r = sec.radius_m[i];
    // Surface slope dr/ds for the normals.
    const uint32_t a = k > 0 ? i - 1 : i;
    const uint32_t b = k + 1 < count ? i + 1 : i;
    const float ds = sec.arc_m[b] - sec.arc_m[a];
    const float slope = ds > 1e-9f ? (sec.radius_m[b] - sec.radius_m[a]) / ds : 0.0f;
    const float v = sec.arc_m[i] * tube.v_scale;
    const auto ring_start = static_cast<uint32_t>(out.positions.size());
    for (int j = 0; j <= m; ++j) {
      const size_t jj = static_cast<size_t>(j);
      if (j == m) {
        const Vec3 seam_p = out.positions[ring_start], seam_n = out.normals[ring_start];
        out.positions.push_back(seam_p);
        out.normals.push_back(seam_n);
        out.uvs.push_back(Vec2(1.0f, v));
        break;
      }
      const Vec3 radial = ex * trig.cos_t[jj] + ey * trig.sin_t[jj];
      out.positions.push_back(sec.positions[i] + radial * (r * trig.lobe[jj]));
      out.normals.push_back(safe_normalize(radial - t * slope, radial));
      out.uvs.push_back(Vec2(static_cast<float>(j) / static_cast<float>(m), v));
    }
  }
}

// The tube's triangles after its base cap centre (`base_vertex`) and rings: the base cap, the
// sides, and the tip — a single vertex for a pointed end, a flat cap otherwise.
void add_tube_triangles(TriangleMesh& out, const StemSections& sec, const Tube& tube, uint32_t base_vertex,
                        const Vec3& tip_axis) {
  const int m = tube.m;
  const uint32_t stride = static_cast<uint32_t>(m) + 1;
  const uint32_t ring0 = base_vertex + 1;
  // Base cap, facing −t.
  for (uint32_t j = 0; j < static_cast<uint32_t>(m); ++j)
    out.triangles.emplace_back(base_vertex, ring0 + j + 1, ring0 + j);
  // Sides.
  for (uint32_t k = 0; k + 1 < tube.rings; ++k) {
    const uint32_t r0 = ring0 + k * stride, r1 = r0 + stride;
    for (uint32_t j = 0; j < static_cast<uint32_t>(m); ++j) {
      out.triangles.emplace_back(r0 + j, r0 + j + 1, r1 + j + 1);
      out.triangles.emplace_back(r0 + j, r1 + j + 1, r1 + j);
    }
  }
  // Tip.
  const uint32_t last_ring = ring0 + (tube.rings - 1) * stride;
  const auto tip = static_cast<uint32_t>(out.positions.size());
  const uint32_t last = tube.first + tube.count - 1;
  out.positions.push_back(sec.positions[last]);
  out.normals.push_back(tip_axis);
  out.uvs.push_back(Vec2(0.5f, sec.arc_m[last] * tube.v_scale));
  for (uint32_t j = 0; j < static_cast<uint32_t>(m); ++j)
    out.triangles.emplace_back(last_ring + j, last_ring + j + 1, tip);
}

// Stem s's tube into `out`.
void mesh_stem(TriangleMesh& out, const TreeModel& model, size_t s, const TreeMeshOptions& options, RingTrig& trig,
               std::vector<Vec3>& tangents) {
  const TreeStems& stems = model.stems;
  const StemSections& sec = model.sections;
  Tube tube{};
  tube.first = stems.first_section[s];
  tube.count = stems.section_count[s];
  tube.m = radial_segments_for_level(options, stems.level[s], stems.lobes[s]);
  update_ring_trig(trig, tube.m, stems.lobes[s], stems.lobe_depth[s]);
  tube.v_scale = 1.0f / (kTwoPi * std::max(stems.base_radius_m[s], 1e-6f));
  ring_tangents(sec, tube.first, tube.count, tangents);
  const bool pointed_tip = sec.radius_m[tube.first + tube.count - 1] <= kTipRadius;
  tube.rings = pointed_tip ? tube.count - 1 : tube.count;

  const auto base_vertex = static_cast<uint32_t>(out.positions.size());
  // Base cap centre.
  out.positions.push_back(sec.positions[tube.first]);
  out.normals.push_back(-tangents[0]);
  out.uvs.push_back(Vec2(0.5f, sec.arc_m[tube.first] * tube.v_scale));
  add_rings(out, sec, tube, trig, tangents);
  add_tube_triangles(out, sec, tube, base_vertex, tangents[tube.count - 1]);
}

// The leaves as quads.
void add_leaf_quads(const TreeLeaves& leaves, LeafQuads& q) {
  q.corners.reserve(4 * leaves.size());
  q.shapes.reserve(leaves.size());
  q.stem = leaves.stem;
  for (size_t i = 0; i < leaves.size(); ++i) {
    const Frame& f = leaves.frames[i];
    // u runs along cross(blade, normal) so the corners are counter-clockwise seen from frames.y.
    const Vec3 across = glm::cross(f.z, f.y) * leaves.width_m[i];
    const Vec3 along = f.z * leaves.length_m[i];
    const Vec3 p0 = leaves.positions[i] - 0.5f * across;
    q.corners.push_back(p0);
    q.corners.push_back(p0 + across);
    q.corners.push_back(p0 + across + along);
    q.corners.push_back(p0 + along);
    q.shapes.push_back(leaves.shapes[i]);
  }
}

}  // namespace

TreeMesh make_tree_mesh(const TreeModel& model, const TreeMeshOptions& options) {
  TreeMesh mesh;
  const TreeStems& stems = model.stems;
  reserve_stems(mesh.stems, stems, options);
  RingTrig trig;
  std::vector<Vec3> tangents;
  for (size_t s = 0; s < stems.size(); ++s) {
    if (stems.section_count[s] < 2) continue;
    TriangleMesh& out = options.split_dead_stems && stems.is_dead(s) ? mesh.dead_stems : mesh.stems;
    mesh_stem(out, model, s, options, trig, tangents);
  }
  if (options.leaves) add_leaf_quads(model.leaves, mesh.leaves);
  return mesh;
}

}  // namespace sylva
