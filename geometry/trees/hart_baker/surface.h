#pragma once
// The Hart–Baker tree's surface (seed 004 §5.2–5.4): blended cones polygonised where a lateral
// limb meets its parent and stitched to the plain tubes elsewhere as one surface, and bark made
// from a flow of particles running from the trunk base to the branch tips. Readings and measured
// figures: docs/hart_baker.md.

#include "geometry/mesh.h"
#include "geometry/trees/hart_baker/hart_baker.h"
#include "geometry/trees/tree_mesher.h"

#include <span>
#include <vector>

namespace sylva {

// One limb of the skeleton: a truncated cone from `base` (radius R) to `tip` (radius r).
struct BlendCone {
  Vec3 base;
  Vec3 tip;
  float base_radius_m;
  float tip_radius_m;
};

// A joint's blend: where the cones meet, and how far and how thick the blend reaches.
struct BlendJoint {
  Vec3 centre;
  float reach_m;   // the blend fades to the plain cones at this distance from the centre
  float fillet_m;  // the blend adds at most this much material to the union of the cones
};

// Eq. 26–30: the blend of two cones, d − r with d the distance from x to the line segment joining
// their nearest axis points x1 and x2 and r = (d2 r1 + d1 r2)/(d1 + d2); negative inside. Taken
// over every pair of the cones (their minimum, so the field stays continuous where the nearest
// pair changes) and bounded (docs/hart_baker.md "Readings"): never outside the union of the cones,
// never more than the joint's fillet·(1 − |x − centre|/reach)² inside it, the bounds rounded (no
// crease where the fillet meets a limb), and equal to the union beyond `reach_m`. At most 16 cones
// are read.
float blended_cones(const Vec3& x, std::span<const BlendCone> cones, const BlendJoint& joint);

// The closed surface of blended_cones over the axis-aligned cube of half-size `half_m` about the
// joint's centre, `cells` cells across, by marching tetrahedra (6 per cell, split along the same
// diagonal so neighbouring cells share their faces' triangulation). The grid's outer layer counts
// as outside, so the surface closes where the limbs leave the cube — those caps lie inside the
// limbs' tubes. Vertices are moved onto the surface along their grid edge (regula falsi); normals
// are the field's gradient. Every edge is shared by exactly two triangles.
TriangleMesh polygonise_joint(std::span<const BlendCone> cones, const BlendJoint& joint, float half_m, int cells);

// Where a stitched joint opens one of its limbs (docs/hart_baker.md "Blended joints"): the joint
// mesh is cut by the plane through `origin` facing `normal` (away from the node) within `radius_m`
// of the limb's axis, and the limb's tube starts again, `gap_m` further out, at the ring of the
// section `ring_arc_m` along `stem` (plan_hart_baker_joints adds it). The band between the two is the
// stitch.
struct JointCut {
  int32_t stem = -1;
  float ring_arc_m = 0;
  bool toward_tip = true;  // the limb leaves the node toward the stem's tip (false: its base)
  Vec3 origin{0.0f};
  Vec3 normal{0.0f, 0.0f, 1.0f};
  float radius_m = 0;
  float gap_m = 0;
  std::vector<uint32_t> loop;  // the joint mesh's open boundary there, in order around the limb
};

// A piece of a limb's tube between two of its rings as the shared mesher draws it: a prism on a
// regular polygon of `sides` sides (0: the round cone) whose corners lie on the cone, the first
// towards `ex`, turning towards `ey` (both across the piece's axis), between the planes of its
// rings (through the cone's ends, facing `base_axis` and `tip_axis`, the rings' axes). Its
// corners are rounded by `rounding_m` (about a marching cell, which cannot follow a sharp edge).
struct TubePiece {
  BlendCone cone;
  Vec3 ex{1.0f, 0.0f, 0.0f};
  Vec3 ey{0.0f, 1.0f, 0.0f};
  int sides = 0;
  float rounding_m = 0;
  Vec3 base_axis{0.0f, 0.0f, 1.0f};
  Vec3 tip_axis{0.0f, 0.0f, 1.0f};
};

// Blended joints meshed together: one node's, or a cluster's whose limbs meet before their blends
// fade (short yearly segments, whorls). A stitched plan is the only surface between its nodes and
// its cuts: its mesh is open at the cuts, the tubes of `inside` are dropped whole and the cut
// stems' tubes from the node side to their rings. Otherwise (a limb too short to leave the blend,
// a cut that is not one clean ring, more than 16 limbs) each node's joint is the closed mesh of
// every cone near it, drawn over the tubes, in a plan of its own.
struct JointPlan {
  std::vector<int32_t> nodes;      // the stems at whose tips the joints sit
  std::vector<BlendJoint> joints;  // their blends
  Vec3 lo{0.0f}, hi{0.0f};         // the polygonised box
  float cell_m = 0;
  std::vector<BlendCone> cones;   // the field's limbs, one cone per stem, blended
  std::vector<TubePiece> pieces;  // stitched: the limbs' tubes piece by piece, whose union it takes
  bool stitched = false;
  std::vector<JointCut> cuts;
  std::vector<int32_t> inside;
  TriangleMesh mesh;  // the polygonised joints, open at the cuts when stitched
};

// A plan's field: the least of its joints' blends (blended_cones) of its cones, where a stitched
// plan takes the union from its pieces — the tubes' own polygons — so that where the blends have
// faded the joint is the tubes' surface. With `round`, the pieces as round cones with round ends
// (the field whose gradient gives the joint's normals, as the tubes' normals are the cones').
float joint_plan_field(const JointPlan& plan, const Vec3& x, bool round = false);

// The blended joints of a Hart–Baker TreeModel: one per node whose thickest lateral is at least
// `surface.joint_min_radius_m` thick, clustered, polygonised and opened at their cuts where they
// are stitched, and the model with a section added at every cut's ring (on the straight piece of
// the stem that holds it), which the tubes are to be meshed from (`options` as for them).
struct HartBakerJoints {
  TreeModel ringed;
  std::vector<JointPlan> plans;
};
HartBakerJoints plan_hart_baker_joints(const TreeModel& model, const HartBakerSurface& surface,
                                       const TreeMeshOptions& options = {});

// A Hart–Baker TreeModel (hart_baker_tree_model) as a TreeMesh: the shared mesher's tubes and
// leaves, a blended joint (plan_hart_baker_joints) wherever a lateral at least
// `surface.joint_min_radius_m` thick leaves its parent — stitched to the tubes, which are trimmed
// inside it, as one surface where it can be — and the bark relief of `params.bark`
// (hart_baker_bark) on the tubes.
TreeMesh make_hart_baker_mesh(const TreeModel& model, const HartBakerParams& params,
                              const TreeMeshOptions& options = {});

// The particle flow of §5.3 over the tubes: one polyline per particle, from the trunk base
// towards the tips (points on the surface, metres). Exposed for tests.
struct BarkFlow {
  std::vector<std::vector<Vec3>> lines;
  std::vector<std::vector<int32_t>> stems;  // the stem each point lies on
};
BarkFlow hart_baker_bark_flow(const TreeModel& model, const HartBakerParams& params);

// Spotted or ribbon bark (§5.4) as relief triangles placed along the flow lines; empty for
// smooth bark. A feature whose anchor lies where a stitched joint of `joints` is the surface
// (between its nodes and its cuts) moves along its normal onto the joint's surface, so it neither
// floats over the tube taken away there nor sinks into the fillet.
TriangleMesh hart_baker_bark(const TreeModel& model, const HartBakerParams& params,
                             std::span<const JointPlan> joints = {});

}  // namespace sylva
