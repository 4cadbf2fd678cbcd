#pragma once
// Internals shared by the Hart–Baker surface's files (surface.h). Not part of the API:
//   joint_blend.cpp   the blended cones (§5.2, eq. 26–30) and marching tetrahedra;
//   joint_field.cpp   a joint plan's field, the tubes' pieces blended;
//   joint_cut.cpp     opening a joint at a cut and zipping it to the tube's ring;
//   joint_layout.cpp  following the limbs out of a cluster of joints to their cuts;
//   joint_plan.cpp    clustering, polygonising and ringing the joints (plan_hart_baker_joints);
//   bark_flow.cpp     the particle flow over the limbs (§5.3);
//   bark.cpp          the bark's relief along the flow (§5.4);
//   surface.cpp       the mesh: tubes, joints and bark as one TreeMesh.

#include "geometry/trees/hart_baker/surface.h"

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace sylva::surface_detail {

// A non-owning reference to a scalar field x ↦ f(x): the callable must outlive the call it is
// passed to.
class FieldRef {
 public:
  template <class F>
  explicit FieldRef(const F& f)
      : object_(&f), call_([](const void* o, const Vec3& x) -> float { return (*static_cast<const F*>(o))(x); }) {}
  float operator()(const Vec3& x) const { return call_(object_, x); }

 private:
  const void* object_;
  float (*call_)(const void*, const Vec3&);
};

// --- joint_blend.cpp ------------------------------------------------------------------------

struct ConeDistance {
  float d;     // distance from x to the nearest axis point
  float r;     // the cone's radius there (eq. 27)
  Vec3 point;  // the nearest axis point
};

ConeDistance cone_distance(const Vec3& x, const BlendCone& c);

// blended_cones with the union of the cones given as f1 (the same limbs, piece by piece).
float blend_field(const Vec3& x, std::span<const BlendCone> cones, float f1, const BlendJoint& joint);

// Marching tetrahedra over the box of `cells` cells of side h from `lo` (polygonise_joint), the
// surface of `field_at`, its normals the gradient of `normal_at`.
//
// Only the signs of the grid values decide the triangles, and only values next to a sign change or
// the border are read again, so far from the surface a block of grid points takes the value at
// its centre: the field lies between f1 − fillet·s² and f1 (blended_cones), f1 a union of cones
// changing by at most 1.2 per metre, so a centre value beyond 1.2 × (the block's reach plus a
// cell's diagonal) + the most fillet·s² of the joints in `joints` over that ball gives the whole
// block and its neighbours the same sign.
TriangleMesh polygonise_box(FieldRef field_at, FieldRef normal_at, const Vec3& lo, const glm::ivec3& cells, float h,
                            std::span<const BlendJoint> joints);

// --- joint_field.cpp ------------------------------------------------------------------------

// A ball holding a tube piece (its centre, and the most a point of the piece lies from it).
struct PieceBall {
  Vec3 centre;
  float radius;
};

std::vector<PieceBall> piece_balls(std::span<const TubePiece> pieces);

// The field of a joint plan: its joints' blends of its cones, the least (JointPlan).
float plan_field(const Vec3& x, std::span<const BlendCone> cones, std::span<const TubePiece> pieces,
                 std::span<const PieceBall> balls, std::span<const BlendJoint> joints, bool round);

// --- joint_cut.cpp --------------------------------------------------------------------------

// Opens the closed joint mesh where a limb leaves it: drops what lies beyond the cut's plane
// within its cylinder and splits the triangles crossing the plane. The new vertices — one loop —
// are moved onto the field's zero set within the plane, given the field's gradient as normal, and
// returned in order around the limb. False (mesh untouched) when the cut is not clean: something
// else crosses the cylinder beyond the plane, or the boundary is not one loop around the axis.
bool open_joint(TriangleMesh& mesh, JointCut& cut, FieldRef field, FieldRef normal_at, float cell);

// The band between a cut's open loop (joint vertices) and its ring (tube vertices ring..ring+m,
// the last repeating the first): both walked once around the limb's axis by angle, merged.
void zipper(TriangleMesh& mesh, const JointCut& cut, uint32_t loop_offset, uint32_t ring, uint32_t m);

// --- joint_layout.cpp -----------------------------------------------------------------------

// A stem as one cone from its first section to its last.
struct StemCone {
  BlendCone cone;
  Vec3 lo, hi;  // bounds, radius included
};

StemCone stem_cone(const TreeModel& model, size_t s);

// Children of every stem.
std::vector<std::vector<int32_t>> stem_children(const TreeModel& model);

inline bool is_lateral(const TreeModel& model, size_t s) {
  const int32_t p = model.stems.parent[s];
  return p >= 0 && model.stems.level[s] > model.stems.level[static_cast<size_t>(p)];
}

inline Vec3 axis_point(const BlendCone& c, float t) { return c.base + (c.tip - c.base) * t; }

// The angle of direction v about a stem's frame (0 along frame.x).
inline float angle_in(const Frame& f, const Vec3& v) { return std::atan2(glm::dot(v, f.y), glm::dot(v, f.x)); }

inline float wrap(float a) {
  a = std::fmod(a, 2 * kPi);
  return a < 0 ? a + 2 * kPi : a;
}

// A node with a blended joint.
struct NodeJoint {
  int32_t stem;  // the joint sits at its tip
  BlendJoint joint;
  float half;     // the closed joint's cube: half-size,
  int cells;      // cells across
  float cell;     // and their size
  float lateral;  // the thickest lateral's base radius
  float far;      // how far out its limbs are cut at least
};

// How a cluster of joints is laid out as one surface with the tubes.
struct ClusterLayout {
  enum class Result { Ok, Join, Fails } result = Result::Fails;
  int32_t join = -1;  // the joint to take into the cluster (Join)
  std::vector<int32_t> field;
  std::vector<JointCut> cuts;
  std::vector<int32_t> inside;
  Vec3 lo{0.0f}, hi{0.0f};
  float cell = 0;
};

// Lays out a cluster of joints (docs/hart_baker.md "Blended joints"): every limb at its nodes (the
// parent down, each child at least half a cell thick up) is followed out of the blends, through
// the stretches joining two of its nodes, and cut where every blend has faded and no other limb
// is within two cells, with a ring 1.5 cells further out; the box holds the nodes' cubes, the
// limbs inside and the cuts.
ClusterLayout layout_cluster(const std::vector<size_t>& members, const TreeModel& model,
                             const std::vector<std::vector<int32_t>>& children, const std::vector<int32_t>& joint_of,
                             const std::vector<NodeJoint>& nodes, const std::vector<StemCone>& cones, float ahead);

}  // namespace sylva::surface_detail
