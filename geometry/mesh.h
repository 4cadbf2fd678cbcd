#pragma once
// Plain mesh data shared by the generators, mesh import/export and the renderer.
// Units are metres; Z is up. Elements refer to vertices by index.

#include "core/math.h"
#include "geometry/leaf_shape.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace sylva {

// An indexed triangle mesh. `normals` and `uvs` are per vertex and either empty or the same size
// as `positions`; without normals the renderer shades with the geometric normal.
struct TriangleMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<Vec2> uvs;
  std::vector<glm::uvec3> triangles;
};

// Leaves as planar quads, four consecutive corners per leaf, counter-clockwise seen from the
// leaf's upper (adaxial) side. Corner k has leaf coordinates (u, v) = (0,0), (1,0), (1,1), (0,1):
// u runs across the blade, v from the petiole end (v = 0) to the tip (v = 1). The outline of
// `shapes[i]` is an alpha mask over that unit square (geometry/leaf_shape.h). `stem[i]` is the
// index of the TreeModel stem carrying leaf i (TreeLeaves::stem), so per-leaf results can be tied
// back to the branch; `stem` is empty for leaves that do not come from a tree model (leaf clouds).
struct LeafQuads {
  std::vector<Vec3> corners;
  std::vector<LeafShape> shapes;
  std::vector<int32_t> stem;  // empty, or one entry per leaf

  size_t size() const { return shapes.size(); }
};

// What a tree generator's mesher produces: bark tubes and leaf quads, in the tree's frame
// (base of the trunk at the origin, Z up).
struct TreeMesh {
  TriangleMesh stems;
  // Dead branches' tubes when the mesher was asked to keep them apart (TreeMeshOptions::
  // split_dead_stems), so a scene can give them their own bark; empty otherwise.
  TriangleMesh dead_stems;
  LeafQuads leaves;
};

// Appends `src` to `dst`, re-indexing; normals/uvs are kept only if both meshes have them.
void append_mesh(TriangleMesh& dst, const TriangleMesh& src);

// Axis-aligned bounds of a set of points; {+inf, -inf} when empty.
struct Bounds3 {
  Vec3 lo{std::numeric_limits<float>::infinity()};
  Vec3 hi{-std::numeric_limits<float>::infinity()};
  void extend(const Vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return lo.x > hi.x; }
};
Bounds3 bounds_of(const TreeMesh& mesh);
// The axis-aligned bounds of `object`'s eight corners moved by an affine transform; empty stays empty.
Bounds3 transformed(const Bounds3& object, const Mat4& world_from_object);

// Area of one leaf quad (two triangles), not counting the alpha cut-out.
float leaf_quad_area(const LeafQuads& leaves, size_t i);

}  // namespace sylva
