// Tree meshing (geometry/trees/tree_mesher.h): closed tubes, normals, UVs, leaf quads.

#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/weber_penn/weber_penn.h"
#include "tests/geometry/trees/wp_test_species.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <tuple>

namespace sylva {
namespace {

// Checks that a triangle mesh is closed and consistently oriented once vertices at the same
// position are welded: every directed edge appears once and its reverse once.
::testing::AssertionResult is_watertight(const TriangleMesh& mesh) {
  std::map<std::tuple<float, float, float>, uint32_t> weld;
  std::vector<uint32_t> id(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3& p = mesh.positions[i];
    id[i] = weld.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<uint32_t>(weld.size())).first->second;
  }
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const glm::uvec3& t : mesh.triangles) {
    const uint32_t a = id[t.x], b = id[t.y], c = id[t.z];
    if (a == b || b == c || a == c) continue;  // degenerate (e.g. a zero-radius ring): no edges
    ++directed[{a, b}];
    ++directed[{b, c}];
    ++directed[{c, a}];
  }
  for (const auto& [edge, n] : directed) {
    if (n != 1) return ::testing::AssertionFailure() << "directed edge used " << n << " times";
    const auto rev = directed.find({edge.second, edge.first});
    if (rev == directed.end() || rev->second != 1) return ::testing::AssertionFailure() << "open edge";
  }
  return ::testing::AssertionSuccess();
}

// A model holding only stem `s` of `m` (with its sections).
TreeModel single_stem(const TreeModel& m, size_t s) {
  TreeModel one;
  const uint32_t first = m.stems.first_section[s], count = m.stems.section_count[s];
  one.stems.level = {m.stems.level[s]};
  one.stems.parent = {-1};
  one.stems.clone_of = {-1};
  one.stems.first_section = {0};
  one.stems.section_count = {count};
  one.stems.length_m = {m.stems.length_m[s]};
  one.stems.base_radius_m = {m.stems.base_radius_m[s]};
  one.stems.offset_m = {0.0f};
  one.stems.lobes = {m.stems.lobes[s]};
  one.stems.lobe_depth = {m.stems.lobe_depth[s]};
  for (uint32_t k = first; k < first + count; ++k) {
    one.sections.positions.push_back(m.sections.positions[k]);
    one.sections.frames.push_back(m.sections.frames[k]);
    one.sections.radius_m.push_back(m.sections.radius_m[k]);
    one.sections.arc_m.push_back(m.sections.arc_m[k]);
  }
  return one;
}

TreeModel straight_stem(float taper_end_radius) {
  TreeModel m;
  m.stems.level = {1};
  m.stems.parent = {-1};
  m.stems.clone_of = {-1};
  m.stems.first_section = {0};
  m.stems.section_count = {3};
  m.stems.length_m = {2.0f};
  m.stems.base_radius_m = {0.1f};
  m.stems.offset_m = {0.0f};
  m.stems.lobes = {0};
  m.stems.lobe_depth = {0.0f};
  m.sections.positions = {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}};
  m.sections.frames = {Frame{}, Frame{}, Frame{}};
  m.sections.radius_m = {0.1f, 0.05f, taper_end_radius};
  m.sections.arc_m = {0.0f, 1.0f, 2.0f};
  return m;
}

TEST(TreeMesher, StraightStemCountsNormalsAndUVs) {
  TreeMeshOptions o;
  o.radial_segments = {16, 8, 6, 4};
  const TreeMesh cone = make_tree_mesh(straight_stem(0.0f), o);
  // Base centre + 2 rings of 9 (seam duplicated) + tip; base fan 8, one band 16, tip fan 8.
  EXPECT_EQ(cone.stems.positions.size(), 1u + 2u * 9u + 1u);
  EXPECT_EQ(cone.stems.triangles.size(), 8u + 16u + 8u);
  EXPECT_TRUE(is_watertight(cone.stems));
  const TreeMesh cylinder = make_tree_mesh(straight_stem(0.05f), o);
  EXPECT_EQ(cylinder.stems.triangles.size(), 8u + 2u * 16u + 8u);
  EXPECT_TRUE(is_watertight(cylinder.stems));
  for (size_t i = 0; i < cylinder.stems.positions.size(); ++i) {
    EXPECT_NEAR(glm::length(cylinder.stems.normals[i]), 1.0f, 1e-5f);
    const Vec2 uv = cylinder.stems.uvs[i];
    EXPECT_GE(uv.x, 0.0f);
    EXPECT_LE(uv.x, 1.0f);
    // v = distance along the stem / base circumference.
    EXPECT_NEAR(uv.y, cylinder.stems.positions[i].z / (kTwoPi * 0.1f), 1e-5f);
  }
  // Side normals point outward (and tilt up where the radius shrinks).
  const Vec3 p = cylinder.stems.positions[2], n = cylinder.stems.normals[2];
  EXPECT_GT(glm::dot(Vec3(p.x, p.y, 0.0f), n), 0.0f);
  EXPECT_GT(n.z, 0.0f);
  // Outward winding: the geometric normal of a side triangle agrees with the vertex normals.
  const glm::uvec3 t = cylinder.stems.triangles[8];
  const Vec3 g = glm::cross(cylinder.stems.positions[t.y] - cylinder.stems.positions[t.x],
                            cylinder.stems.positions[t.z] - cylinder.stems.positions[t.x]);
  EXPECT_GT(glm::dot(g, cylinder.stems.normals[t.x]), 0.0f);
}

TEST(TreeMesher, QualityAndLobesSetRadialResolution) {
  TreeMeshOptions o;
  EXPECT_EQ(radial_segments_for_level(o, 0, 0), 16);
  EXPECT_EQ(radial_segments_for_level(o, 7, 0), 4);   // deeper levels use the last entry
  EXPECT_EQ(radial_segments_for_level(o, 0, 5), 20);  // 4 vertices per lobe
  o.quality = 0.25f;
  EXPECT_EQ(radial_segments_for_level(o, 0, 0), 4);
  EXPECT_EQ(radial_segments_for_level(o, 3, 0), 3);  // never below 3
}

TEST(TreeMesher, EveryStemTubeWatertight) {
  // Species with lobes, flare, splits (clones), a helix, and a taper mode beyond 1 each.
  std::vector<WeberPennParams> species = {test::quaking_aspen(), test::california_black_oak(), test::weeping_willow()};
  WeberPennParams spherical = test::quaking_aspen();
  spherical.level[0].taper = 2.0f;
  spherical.level[1].taper = 1.5f;
  spherical.level[2].taper = 2.6f;
  species.push_back(spherical);
  for (size_t k = 0; k < species.size(); ++k) {
    WeberPennParams p = species[k];
    p.leaves = 0;
    if (k == 2) p.levels = 3;
    const TreeModel m = make_weber_penn_tree(p, 12);
    for (size_t s = 0; s < m.stems.size(); s += (m.stems.level[s] >= 2 ? 7 : 1)) {
      const TreeMesh mesh = make_tree_mesh(single_stem(m, s));
      ASSERT_TRUE(is_watertight(mesh.stems)) << "species " << k << " stem " << s;
    }
  }
}

TEST(TreeMesher, ClonesContinueTheirTwinWithoutTwist) {
  WeberPennParams p = test::california_black_oak();
  p.leaves = 0;
  p.levels = 1;
  const TreeModel m = make_weber_penn_tree(p, 3);
  TreeMeshOptions o;
  const TreeMesh mesh = make_tree_mesh(m, o);
  // The trunk's rings keep their reference axis: consecutive ring vertex 0 directions stay close.
  const int ring = radial_segments_for_level(o, 0, p.lobes) + 1;
  const Vec3 c0 = m.sections.positions[0];
  const Vec3 r0 = glm::normalize(mesh.stems.positions[1] - c0);
  const Vec3 r1 = glm::normalize(mesh.stems.positions[1 + static_cast<size_t>(ring)] - m.sections.positions[1]);
  EXPECT_GT(glm::dot(r0, r1), 0.9f);
  int clones = 0;
  for (size_t s = 0; s < m.stems.size(); ++s) {
    if (!m.stems.is_clone(s)) continue;
    ++clones;
    // A clone's first ring lies where its twin's tube passes: same centre and radius.
    const size_t twin = static_cast<size_t>(m.stems.clone_of[s]);
    const Vec3 start = m.sections.positions[m.stems.first_section[s]];
    bool found = false;
    for (uint32_t k = 0; k < m.stems.section_count[twin]; ++k) {
      const uint32_t i = m.stems.first_section[twin] + k;
      if (m.sections.positions[i] == start) {
        found = true;
        EXPECT_EQ(m.sections.radius_m[i], m.sections.radius_m[m.stems.first_section[s]]);
        EXPECT_EQ(m.sections.arc_m[i], m.sections.arc_m[m.stems.first_section[s]]);
      }
    }
    EXPECT_TRUE(found);
  }
  EXPECT_GT(clones, 0);
}

TEST(TreeMesher, LeafQuadsFollowTheLeafFrame) {
  TreeModel m;
  Frame f;  // blade along +z, width along x, upper side +y
  m.leaves.positions = {{1, 2, 3}};
  m.leaves.frames = {f};
  m.leaves.length_m = {0.2f};
  m.leaves.width_m = {0.1f};
  m.leaves.shapes = {LeafShape::Maple5};
  m.leaves.stem = {0};
  const TreeMesh mesh = make_tree_mesh(m);
  ASSERT_EQ(mesh.leaves.size(), 1u);
  EXPECT_EQ(mesh.leaves.shapes[0], LeafShape::Maple5);
  const Vec3* c = &mesh.leaves.corners[0];
  EXPECT_NEAR(leaf_quad_area(mesh.leaves, 0), 0.02f, 1e-7f);
  // Counter-clockwise seen from the upper side (+y), petiole end (v = 0) at the leaf position.
  EXPECT_GT(glm::dot(glm::cross(c[1] - c[0], c[2] - c[0]), f.y), 0.0f);
  EXPECT_NEAR(glm::length(0.5f * (c[0] + c[1]) - Vec3(1, 2, 3)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(0.5f * (c[2] + c[3]) - Vec3(1, 2, 3.2f)), 0.0f, 1e-6f);
  TreeMeshOptions no_leaves;
  no_leaves.leaves = false;
  EXPECT_EQ(make_tree_mesh(m, no_leaves).leaves.size(), 0u);
}

TEST(TreeMesher, LeafQuadsKeepTheirStem) {
  const TreeModel model = make_weber_penn_tree(test::quaking_aspen(), 7);
  const TreeMesh mesh = make_tree_mesh(model);
  ASSERT_GT(model.leaves.size(), 100u);
  ASSERT_EQ(mesh.leaves.stem.size(), mesh.leaves.size());
  EXPECT_EQ(mesh.leaves.stem, model.leaves.stem);
  // Leaves sit on many different stems, every one a real stem of the model.
  std::set<int32_t> stems(mesh.leaves.stem.begin(), mesh.leaves.stem.end());
  EXPECT_GT(stems.size(), 10u);
  EXPECT_GE(*stems.begin(), 0);
  EXPECT_LT(*stems.rbegin(), static_cast<int32_t>(model.stems.size()));
}

}  // namespace
}  // namespace sylva
