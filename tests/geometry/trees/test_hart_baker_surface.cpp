// The Hart–Baker surface (geometry/trees/hart_baker/surface.h): the blended-cone field (§5.2,
// eq. 26–30), the polygonised joint (closed, on the surface, no holes where it meets the tubes),
// the particle flow (§5.3) and the bark relief (§5.4).

#include "geometry/trees/hart_baker/surface.h"

#include "geometry/trees/tree_mesher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <set>

namespace sylva {
namespace {

// A node: a trunk segment, its continuation and a lateral at 50°.
std::vector<BlendCone> y_joint() {
  const Vec3 node(0, 0, 1);
  const Vec3 lateral_dir = glm::normalize(Vec3(std::sin(0.87f), 0, std::cos(0.87f)));
  return {{Vec3(0, 0, 0), node, 0.10f, 0.08f},
          {node, Vec3(0, 0, 2), 0.08f, 0.05f},
          {node, node + lateral_dir * 0.8f, 0.05f, 0.02f}};
}

BlendJoint y_blend() { return {Vec3(0, 0, 1), 0.25f, 0.03f}; }

// A TreeModel of limbs given as cones with their parents and levels, two sections each; every
// child sits `child_offset_m` along its parent.
TreeModel cone_model(const std::vector<BlendCone>& cones, const std::vector<int32_t>& parents,
                     const std::vector<uint8_t>& levels, float child_offset_m = 0.0f) {
  TreeModel m;
  for (size_t s = 0; s < cones.size(); ++s) {
    const BlendCone& c = cones[s];
    m.stems.level.push_back(levels[s]);
    m.stems.parent.push_back(parents[s]);
    m.stems.clone_of.push_back(-1);
    m.stems.first_section.push_back(static_cast<uint32_t>(m.sections.size()));
    m.stems.section_count.push_back(2);
    m.stems.length_m.push_back(glm::length(c.tip - c.base));
    m.stems.base_radius_m.push_back(c.base_radius_m);
    m.stems.offset_m.push_back(parents[s] < 0 ? 0.0f : child_offset_m);
    m.stems.lobes.push_back(0);
    m.stems.lobe_depth.push_back(0.0f);
    const Frame f = Frame::from_z(glm::normalize(c.tip - c.base));
    m.sections.positions.push_back(c.base);
    m.sections.positions.push_back(c.tip);
    m.sections.frames.push_back(f);
    m.sections.frames.push_back(f);
    m.sections.radius_m.push_back(c.base_radius_m);
    m.sections.radius_m.push_back(c.tip_radius_m);
    m.sections.arc_m.push_back(0.0f);
    m.sections.arc_m.push_back(m.stems.length_m.back());
  }
  return m;
}

// The Y node as a TreeModel in hart_baker_tree_model's layout (two sections per stem).
TreeModel y_model() { return cone_model(y_joint(), {-1, 0, 0}, {0, 0, 1}, 1.0f); }

// Edges of a triangle mesh with its vertices welded by position: how many triangles use each
// (undirected, by welded ids) and each direction.
struct WeldedEdges {
  std::vector<uint32_t> id;  // welded id of each vertex
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  std::map<std::pair<uint32_t, uint32_t>, int> undirected;
  std::vector<Vec3> where;  // a position per welded id
};

WeldedEdges weld_edges(const TriangleMesh& mesh) {
  WeldedEdges w;
  std::map<std::array<uint32_t, 3>, uint32_t> ids;
  for (const Vec3& p : mesh.positions) {
    std::array<uint32_t, 3> key{};
    std::memcpy(key.data(), &p, sizeof(key));
    const auto [it, added] = ids.emplace(key, static_cast<uint32_t>(w.where.size()));
    if (added) w.where.push_back(p);
    w.id.push_back(it->second);
  }
  for (const glm::uvec3& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = w.id[t[e]], b = w.id[t[(e + 1) % 3]];
      if (a == b) continue;
      ++w.directed[{a, b}];
      ++w.undirected[{std::min(a, b), std::max(a, b)}];
    }
  return w;
}

// The edges (as pairs of positions) that are not shared by exactly two triangles.
std::set<std::pair<std::array<float, 3>, std::array<float, 3>>> bad_edges(const WeldedEdges& w) {
  std::set<std::pair<std::array<float, 3>, std::array<float, 3>>> bad;
  for (const auto& [edge, count] : w.undirected)
    if (count != 2) {
      const Vec3 a = w.where[edge.first], b = w.where[edge.second];
      bad.insert({{a.x, a.y, a.z}, {b.x, b.y, b.z}});
    }
  return bad;
}

bool in_box(const JointPlan& plan, const Vec3& p) {
  return glm::all(glm::greaterThanEqual(p, plan.lo)) && glm::all(glm::lessThanEqual(p, plan.hi));
}

// Inside a stitched plan's one surface: in its box and short of every cut.
bool in_stitched_region(const JointPlan& plan, const Vec3& p) {
  if (!in_box(plan, p)) return false;
  for (const JointCut& c : plan.cuts) {
    const Vec3 rel = p - c.origin;
    const float along = glm::dot(rel, c.normal);
    if (along > 0 && glm::length(rel - c.normal * along) < c.radius_m) return false;
  }
  return true;
}

// The stems a stitched plan draws: whole ones and the cut ones.
std::vector<int32_t> plan_stems(const JointPlan& plan) {
  std::vector<int32_t> stems = plan.inside;
  for (const JointCut& c : plan.cuts) stems.push_back(c.stem);
  return stems;
}

// The tubes of some of a model's stems, as the shared mesher draws them.
TriangleMesh tubes_of(const TreeModel& model, const std::vector<int32_t>& stems) {
  TreeModel sub = model;
  for (size_t s = 0; s < sub.stems.size(); ++s)
    if (std::find(stems.begin(), stems.end(), static_cast<int32_t>(s)) == stems.end()) sub.stems.section_count[s] = 0;
  TreeMeshOptions options;
  options.leaves = false;
  return make_tree_mesh(sub, options).stems;
}

float cone_union(const Vec3& x, const std::vector<BlendCone>& cones) {
  float f = 1e9f;
  for (const BlendCone& c : cones) {
    const Vec3 ab = c.tip - c.base;
    const float t = std::clamp(glm::dot(x - c.base, ab) / glm::dot(ab, ab), 0.0f, 1.0f);
    f = std::min(f, glm::length(x - (c.base + ab * t)) - ((1 - t) * c.base_radius_m + t * c.tip_radius_m));
  }
  return f;
}

TEST(HartBakerSurface, BlendIsTheConesAwayFromTheJointAndAddsAFilletAtIt) {
  const std::vector<BlendCone> cones = y_joint();
  const BlendJoint joint = y_blend();
  // Beyond the reach the field is the union of the cones.
  for (const Vec3 x : {Vec3(0.3f, 0.1f, 0.4f), Vec3(0.0f, 0.2f, 1.6f), Vec3(0.5f, 0.0f, 1.5f)})
    EXPECT_FLOAT_EQ(blended_cones(x, cones, joint), cone_union(x, cones)) << x.x << " " << x.z;
  // In the crotch between trunk and lateral the blend adds wood: along the bisector of the two
  // axes, some points the union leaves outside are inside the blend.
  const Vec3 bisector = glm::normalize(Vec3(0, 0, 1) + glm::normalize(cones[2].tip - cones[2].base));
  int filled = 0;
  for (float t = 0.02f; t < 0.25f; t += 0.002f) {
    const Vec3 p = joint.centre + bisector * t;
    filled += cone_union(p, cones) > 0 && blended_cones(p, cones, joint) < 0;
  }
  EXPECT_GT(filled, 0);
  // Never outside the union, never more than the fillet inside it.
  for (float z = 0.8f; z < 1.2f; z += 0.01f)
    for (float x = -0.2f; x < 0.2f; x += 0.01f) {
      const Vec3 p(x, 0.03f, z);
      EXPECT_LE(blended_cones(p, cones, joint), cone_union(p, cones));
      EXPECT_GE(blended_cones(p, cones, joint), cone_union(p, cones) - joint.fillet_m - 1e-6f);
    }
}

TEST(HartBakerSurface, PolygonisedJointIsClosedAndLiesOnTheSurface) {
  const std::vector<BlendCone> cones = y_joint();
  const BlendJoint joint = y_blend();
  const float half = 0.28f;
  const int cells = 24;
  const TriangleMesh mesh = polygonise_joint(cones, joint, half, cells);
  ASSERT_GT(mesh.triangles.size(), 500u);
  // Closed and consistently oriented: every directed edge once, its reverse once.
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const glm::uvec3& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << edge.first << "-" << edge.second;
  }
  // Vertices away from the closing caps lie on the implicit surface.
  const float h = 2 * half / cells;
  int on_surface = 0;
  for (const Vec3& p : mesh.positions) {
    const Vec3 d = glm::abs(p - joint.centre);
    if (std::max({d.x, d.y, d.z}) > half - h) continue;
    EXPECT_NEAR(blended_cones(p, cones, joint), 0.0f, 1e-4f);
    ++on_surface;
  }
  EXPECT_GT(on_surface, 200);
  // Outward normals: the enclosed volume is positive and close to the blend's (the union's
  // volume inside the cube plus a fillet).
  double volume = 0;
  for (const glm::uvec3& t : mesh.triangles)
    volume += glm::dot(mesh.positions[t.x], glm::cross(mesh.positions[t.y], mesh.positions[t.z])) / 6.0;
  double sampled = 0;
  const int n = 60;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 p = joint.centre - Vec3(half) + (Vec3(i, j, k) + 0.5f) * (2 * half / n);
        if (blended_cones(p, cones, joint) < 0) sampled += std::pow(2.0 * half / n, 3);
      }
  EXPECT_NEAR(volume, sampled, 0.05 * sampled);
}

// Nearest hit of a ray with a mesh (Möller–Trumbore).
std::optional<float> ray_hit(const TriangleMesh& mesh, const Vec3& o, const Vec3& d) {
  std::optional<float> best;
  for (const glm::uvec3& t : mesh.triangles) {
    const Vec3 a = mesh.positions[t.x], e1 = mesh.positions[t.y] - a, e2 = mesh.positions[t.z] - a;
    const Vec3 p = glm::cross(d, e2);
    const float det = glm::dot(e1, p);
    if (std::abs(det) < 1e-12f) continue;
    const Vec3 s = o - a;
    const float u = glm::dot(s, p) / det;
    if (u < 0 || u > 1) continue;
    const Vec3 q = glm::cross(s, e1);
    const float v = glm::dot(d, q) / det;
    if (v < 0 || u + v > 1) continue;
    const float dist = glm::dot(e2, q) / det;
    if (dist > 0 && (!best || dist < *best)) best = dist;
  }
  return best;
}

TEST(HartBakerSurface, JointAndTubesLeaveNoHoles) {
  // Rays from all around aimed at the joint: the tubes plus the polygonised joint stop each ray
  // where the blended surface does (a hole would let it through to the far side or deeper).
  const TreeModel model = y_model();
  HartBakerParams params;
  params.surface.joint_min_radius_m = 0.0f;
  params.surface.reach = 2.5f;
  const TreeMesh mesh = make_hart_baker_mesh(model, params);
  const TreeMesh tubes = make_tree_mesh(model);
  ASSERT_GT(mesh.stems.triangles.size(), tubes.stems.triangles.size());
  const std::vector<BlendCone> cones = y_joint();
  // The joint the mesher built: reach 2.5 × the thicker of parent tip and lateral base radii.
  const BlendJoint joint{Vec3(0, 0, 1), 2.5f * 0.08f, params.surface.fillet * 0.05f};
  const float cell = 2 * 1.1f * joint.reach_m / static_cast<float>(params.surface.joint_cells);
  int tested = 0;
  for (int i = 0; i < 400; ++i) {
    // Fibonacci directions, aimed at points scattered about the node.
    const float z = 1 - 2 * (i + 0.5f) / 400.0f;
    const float phi = 2.39996323f * static_cast<float>(i);
    const Vec3 dir(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
    const Vec3 target = joint.centre + 0.05f * Vec3(std::sin(3.0f * i), std::cos(5.0f * i), std::sin(7.0f * i));
    const Vec3 origin = target - dir * 1.0f;
    // The blended surface along the ray by small steps then bisection.
    float t0 = 0;
    std::optional<float> surface;
    for (float t = 0; t < 2.0f; t += 0.002f) {
      if (blended_cones(origin + dir * t, cones, joint) < 0) {
        float lo = t0, hi = t;
        for (int k = 0; k < 30; ++k) {
          const float mid = 0.5f * (lo + hi);
          (blended_cones(origin + dir * mid, cones, joint) < 0 ? hi : lo) = mid;
        }
        surface = hi;
        break;
      }
      t0 = t;
    }
    if (!surface || glm::length(origin + dir * *surface - joint.centre) > 0.8f * joint.reach_m) continue;
    // The stitched joint follows the tubes' polygons (flats up to 2 % of the radius inside the
    // cones), so a grazing ray may meet it well before or after the cones: the hit must lie on
    // the surface, and the ray may not pass it.
    const std::optional<float> hit = ray_hit(mesh.stems, origin, dir);
    ASSERT_TRUE(hit.has_value()) << "ray " << i;
    const Vec3 at = origin + dir * *surface;
    const float e = 1e-4f;
    const Vec3 gradient(
        blended_cones(at + Vec3(e, 0, 0), cones, joint) - blended_cones(at - Vec3(e, 0, 0), cones, joint),
        blended_cones(at + Vec3(0, e, 0), cones, joint) - blended_cones(at - Vec3(0, e, 0), cones, joint),
        blended_cones(at + Vec3(0, 0, e), cones, joint) - blended_cones(at - Vec3(0, 0, e), cones, joint));
    if (std::abs(glm::dot(glm::normalize(gradient), dir)) > 0.3f) {  // not grazing
      EXPECT_LT(*hit, *surface + cell) << "ray " << i;
    }
    EXPECT_LT(std::abs(blended_cones(origin + dir * *hit, cones, joint)), 0.3f * cell) << "ray " << i;
    ++tested;
  }
  EXPECT_GT(tested, 150);
}

// Every welded edge of the mesh used by exactly two triangles, once each way.
void expect_closed_and_oriented(const TriangleMesh& mesh) {
  const WeldedEdges w = weld_edges(mesh);
  int open = 0, crowded = 0, misoriented = 0;
  for (const auto& [edge, count] : w.undirected) {
    open += count < 2;
    crowded += count > 2;
    if (count == 2) {
      const auto ab = w.directed.find(edge), ba = w.directed.find({edge.second, edge.first});
      misoriented += ab == w.directed.end() || ba == w.directed.end() || ab->second != 1 || ba->second != 1;
    }
  }
  EXPECT_EQ(open, 0);
  EXPECT_EQ(crowded, 0);
  EXPECT_EQ(misoriented, 0);
}

TEST(HartBakerSurface, StitchedJointAndTubesAreOneClosedSurface) {
  // The node's tubes (trunk, continuation, lateral) meet inside the joint, their rings there
  // coincide or cross; stitched, the joint replaces them and the whole is one closed, consistently
  // oriented surface.
  const TreeModel model = y_model();
  HartBakerParams params;
  params.surface.joint_min_radius_m = 0.0f;
  const HartBakerJoints joints = plan_hart_baker_joints(model, params.surface);
  ASSERT_EQ(joints.plans.size(), 1u);
  const JointPlan& plan = joints.plans[0];
  ASSERT_TRUE(plan.stitched);
  EXPECT_EQ(plan.cuts.size(), 3u);  // down the trunk, up the continuation, up the lateral
  expect_closed_and_oriented(make_hart_baker_mesh(model, params).stems);
  // Without the stitch the same tubes and a closed joint overlap: not one surface (edges of the
  // coincident rings at the node are shared by four triangles).
  const WeldedEdges plain = weld_edges(make_tree_mesh(model).stems);
  EXPECT_FALSE(bad_edges(plain).empty());
}

TEST(HartBakerSurface, JointsWhoseLimbsMeetAreStitchedTogether) {
  // Two nodes 10 cm apart on a trunk, each with a lateral (one towards a corner of the cube, so it
  // leaves through an edge), each blend reaching 20 cm: one cluster, one surface.
  const Vec3 a(0, 0, 1), b(0, 0, 1.1f);
  const Vec3 corner = glm::normalize(Vec3(1, 1, 1));
  const Vec3 side = glm::normalize(Vec3(-std::sin(0.8f), 0, std::cos(0.8f)));
  const std::vector<BlendCone> cones = {{Vec3(0), a, 0.10f, 0.08f},
                                        {a, b, 0.08f, 0.078f},
                                        {a, a + corner * 0.8f, 0.05f, 0.02f},
                                        {b, Vec3(0, 0, 2), 0.078f, 0.05f},
                                        {b, b + side * 0.8f, 0.04f, 0.015f}};
  const TreeModel model = cone_model(cones, {-1, 0, 0, 1, 1}, {0, 0, 1, 0, 1});
  HartBakerParams params;
  const HartBakerJoints joints = plan_hart_baker_joints(model, params.surface);
  ASSERT_EQ(joints.plans.size(), 1u);
  const JointPlan& plan = joints.plans[0];
  EXPECT_TRUE(plan.stitched);
  EXPECT_EQ(plan.nodes.size(), 2u);
  EXPECT_EQ(plan.inside, std::vector<int32_t>{1});  // the stretch between the nodes
  EXPECT_EQ(plan.cuts.size(), 4u);
  expect_closed_and_oriented(make_hart_baker_mesh(model, params).stems);
}

// A grown tree with blended joints (no light pass: every leaf lit).
TreeModel grown_tree(int buds, float bud_break, int years, HartBakerParams& params) {
  params.buds_per_node = buds;
  params.bud_break = bud_break;
  TreeOptions options;
  options.years = years;
  return make_tree(params, 3, options);
}

void expect_one_surface_at_joints(const TreeModel& model, const HartBakerParams& params, size_t least_cuts) {
  const HartBakerJoints joints = plan_hart_baker_joints(model, params.surface);
  const TreeMesh mesh = make_hart_baker_mesh(model, params);
  size_t stitched = 0, most_cuts = 0;
  for (const JointPlan& plan : joints.plans) {
    stitched += plan.stitched;
    most_cuts = std::max(most_cuts, plan.cuts.size());
  }
  ASSERT_GT(stitched, 0u);
  EXPECT_GE(most_cuts, least_cuts);
  // No open or crowded edge near a stitched joint that the tubes alone (the same tubes, rings
  // included) do not have: the stitch leaves no crack.
  const auto before = bad_edges(weld_edges(make_tree_mesh(joints.ringed).stems));
  const WeldedEdges after = weld_edges(mesh.stems);
  int near_joints = 0, new_bad = 0;
  for (const auto& [edge, count] : after.undirected) {
    const Vec3 a = after.where[edge.first], b = after.where[edge.second];
    const Vec3 mid = 0.5f * (a + b);
    bool near = false;
    for (const JointPlan& plan : joints.plans) near = near || (plan.stitched && in_box(plan, mid));
    if (!near) continue;
    ++near_joints;
    if (count != 2 && !before.count({{a.x, a.y, a.z}, {b.x, b.y, b.z}})) {
      ++new_bad;
      ADD_FAILURE() << a.x << " " << a.y << " " << a.z << " - " << b.x << " " << b.y << " " << b.z << " x" << count;
    }
  }
  EXPECT_GT(near_joints, 1000);
  EXPECT_EQ(new_bad, 0);
  for (const JointPlan& plan : joints.plans) {
    if (!plan.stitched) continue;
    // No tube triangle of the joint's limbs is left short of the cuts (the tubes were there).
    const TriangleMesh tubes = tubes_of(joints.ringed, plan_stems(plan));
    std::set<std::array<float, 3>> on_tube;
    for (const Vec3& p : tubes.positions) on_tube.insert({p.x, p.y, p.z});
    auto tube_triangle = [&](const TriangleMesh& m, const glm::uvec3& t) {
      for (int e = 0; e < 3; ++e) {
        const Vec3& p = m.positions[t[e]];
        if (!on_tube.count({p.x, p.y, p.z})) return false;
      }
      return true;
    };
    auto centroid = [](const TriangleMesh& m, const glm::uvec3& t) {
      return (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0f;
    };
    int were = 0, left = 0;
    for (const glm::uvec3& t : tubes.triangles) were += in_stitched_region(plan, centroid(tubes, t));
    for (const glm::uvec3& t : mesh.stems.triangles)
      left += tube_triangle(mesh.stems, t) && in_stitched_region(plan, centroid(mesh.stems, t));
    EXPECT_GT(were, 0);
    EXPECT_EQ(left, 0);
    // The joint's own vertices lie on its field's zero set (the loops too: moved onto it).
    for (const Vec3& p : plan.mesh.positions)
      if (in_stitched_region(plan, p)) {
        EXPECT_NEAR(joint_plan_field(plan, p), 0.0f, 1e-4f) << p.x << " " << p.y << " " << p.z;
      }
  }
}

TEST(HartBakerSurface, GrownTreeJointsAreOneSurfaceWithTheTubes) {
  HartBakerParams params;
  const TreeModel model = grown_tree(2, 0.7f, 10, params);
  expect_one_surface_at_joints(model, params, 4);
}

TEST(HartBakerSurface, WhorlJointsAreOneSurfaceWithTheTubes) {
  // Four laterals a node (a conifer's whorl): the parent, the continuation and four laterals cut.
  HartBakerParams params;
  const TreeModel model = grown_tree(4, 1.0f, 8, params);
  expect_one_surface_at_joints(model, params, 6);
}

TEST(HartBakerSurface, BarkOverAStitchedJointLiesOnItsSurface) {
  // Spots placed where a stitched joint replaced the tubes sit on the joint's surface: within the
  // spots' height of its zero set, neither floating over the flats nor sunk in the fillet (as they
  // are when placed on the limbs' cones).
  HartBakerParams params;
  const TreeModel model = grown_tree(2, 0.7f, 10, params);
  params.bark.kind = BarkKind::Spotted;
  params.bark.min_radius_m = 0.01f;
  const HartBakerJoints joints = plan_hart_baker_joints(model, params.surface);
  auto off_surface = [&](const TriangleMesh& bark, int& inside) {
    int off = 0;
    inside = 0;
    for (const Vec3& p : bark.positions)
      for (const JointPlan& plan : joints.plans)
        if (plan.stitched && in_stitched_region(plan, p)) {
          ++inside;
          off += std::abs(joint_plan_field(plan, p)) > params.bark.height_m + 1e-3f;
        }
    return off;
  };
  int inside = 0;
  EXPECT_EQ(off_surface(hart_baker_bark(model, params, joints.plans), inside), 0);
  EXPECT_GT(inside, 50);
  EXPECT_GT(off_surface(hart_baker_bark(model, params), inside), 0);
}

TEST(HartBakerSurface, SmoothUnblendedMeshIsTheSharedMeshers) {
  const TreeModel model = y_model();
  HartBakerParams params;
  params.surface.blend = false;
  const TreeMesh a = make_hart_baker_mesh(model, params);
  const TreeMesh b = make_tree_mesh(model);
  EXPECT_EQ(a.stems.positions, b.stems.positions);
  EXPECT_EQ(a.stems.triangles, b.stems.triangles);
  params.surface.blend = true;
  params.surface.joint_min_radius_m = 0.06f;  // thicker than the lateral: nothing to blend
  EXPECT_EQ(make_hart_baker_mesh(model, params).stems.triangles, b.stems.triangles);
}

TEST(HartBakerSurface, ParticlesFlowFromTheTrunkBaseOverEveryLimbToItsTip) {
  const TreeModel model = y_model();
  HartBakerParams params;
  params.bark.spacing_m = 0.02f;
  const BarkFlow flow = hart_baker_bark_flow(model, params);
  const std::vector<BlendCone> cones = y_joint();
  ASSERT_FALSE(flow.lines.empty());
  std::vector<int> lines_on(cones.size(), 0);
  std::vector<int> reaching_tip(cones.size(), 0);
  int from_base = 0;
  for (size_t l = 0; l < flow.lines.size(); ++l) {
    if (std::abs(flow.lines[l].front().z) < 1e-5f) ++from_base;
    int32_t last = -1;
    for (size_t k = 0; k < flow.lines[l].size(); ++k) {
      const int32_t s = flow.stems[l][k];
      if (s != last) ++lines_on[static_cast<size_t>(s)];
      last = s;
      // On the cone's surface.
      const BlendCone& c = cones[static_cast<size_t>(s)];
      const Vec3 ab = c.tip - c.base;
      const float t = std::clamp(glm::dot(flow.lines[l][k] - c.base, ab) / glm::dot(ab, ab), 0.0f, 1.0f);
      EXPECT_NEAR(glm::length(flow.lines[l][k] - (c.base + ab * t)), (1 - t) * c.base_radius_m + t * c.tip_radius_m,
                  1e-4f);
      if (glm::length(flow.lines[l][k] - c.tip) <= c.tip_radius_m + 1e-4f) ++reaching_tip[static_cast<size_t>(s)];
    }
  }
  // The trunk base ring starts lines; every limb carries a ring within the chain's link lengths
  // (at most 1.5 spacings apart, at least half a spacing) and the flow reaches the tips.
  EXPECT_GE(from_base, static_cast<int>(std::ceil(2 * 3.14159f * 0.10f / 0.03f)));
  for (size_t s = 0; s < cones.size(); ++s) {
    const float circumference = 2 * 3.14159f * cones[s].base_radius_m;
    EXPECT_GE(lines_on[s], static_cast<int>(std::ceil(circumference / 0.03f))) << "stem " << s;
    EXPECT_LE(lines_on[s], static_cast<int>(std::floor(circumference / 0.01f)) + 1) << "stem " << s;
  }
  EXPECT_GT(reaching_tip[1], 0);
  EXPECT_GT(reaching_tip[2], 0);
  // Lines continue through the node: some trunk lines go on up the lateral.
  int into_lateral = 0;
  for (size_t l = 0; l < flow.lines.size(); ++l)
    if (flow.stems[l].front() == 0 && flow.stems[l].back() == 2) ++into_lateral;
  EXPECT_GT(into_lateral, 0);
}

TEST(HartBakerSurface, BarkKindsMakeReliefOnTheLimbs) {
  const TreeModel model = y_model();
  HartBakerParams params;
  EXPECT_TRUE(hart_baker_bark(model, params).triangles.empty());  // smooth
  const std::vector<BlendCone> cones = y_joint();
  for (const BarkKind kind : {BarkKind::Spotted, BarkKind::Ribbon}) {
    params.bark.kind = kind;
    params.bark.min_radius_m = 0.045f;  // the trunk segment and the lateral's base
    const TriangleMesh bark = hart_baker_bark(model, params);
    ASSERT_GT(bark.triangles.size(), 50u);
    // Every vertex stands on the bark, at most the feature height above it.
    for (const Vec3& p : bark.positions)
      EXPECT_LE(std::abs(cone_union(p, cones)), params.bark.height_m + 1e-3f) << p.x << " " << p.y << " " << p.z;
    // Denser bark, more features.
    params.bark.density = 0.2f;
    EXPECT_LT(hart_baker_bark(model, params).triangles.size(), bark.triangles.size());
    params.bark.density = 0.7f;
  }
}

}  // namespace
}  // namespace sylva
