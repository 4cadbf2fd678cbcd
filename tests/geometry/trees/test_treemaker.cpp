// TREE-MAKER particle growth (geometry/trees/treemaker/treemaker.h, Neighbors & Hodges §II):
// determinism, branching statistics, gravity, widths, one leaf definition per branch end, the
// tri=/ln= elements as leaf quads, material slots and the growth budget.

#include "core/error.h"
#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/treemaker/treemaker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <tuple>

namespace sylva {
namespace {

// One upright particle and one rule; callers adjust.
TreeMakerTemplate basic_template() {
  TreeMakerTemplate t;
  t.iterations = 6;
  t.gravity = 0.0f;
  t.colors = {{"brown", Vec3(1.0f, 0.9f, 0.2f)}, {"green", Vec3(0, 1, 0)}, {"white", Vec3(1, 1, 1)}};
  TreeMakerBranchRule rule;
  rule.level = 1;
  rule.number = {0.4f, 1.6f};
  rule.choices = {{1.0f, {40.0f, 60.0f}, {0.0f, 360.0f}, {0.6f, 0.8f}}};
  t.branches = {rule};
  TreeMakerParticle p;
  p.mag = {15.0f, 25.0f};
  p.acc = -0.8f;
  p.growth = 0.4f;
  p.color = 0;
  p.brightness = {0.2f, 0.5f};
  t.particles = {p};
  TreeMakerLeaf leaf;
  leaf.p = 1.0f;
  leaf.coord = TreeMakerCoord::Leaf;
  leaf.elements = {{{Vec3(0, 0, 0), Vec3(0, -9, 3), Vec3(-3, -3, 4)}, 1, {0.4f, 0.8f}}};
  t.leaves = {leaf};
  return t;
}

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool same_model(const TreeModel& a, const TreeModel& b) {
  return same_bits(a.stems.level, b.stems.level) && same_bits(a.stems.parent, b.stems.parent) &&
         same_bits(a.stems.section_count, b.stems.section_count) &&
         same_bits(a.sections.positions, b.sections.positions) && same_bits(a.sections.radius_m, b.sections.radius_m) &&
         same_bits(a.sections.arc_m, b.sections.arc_m) && same_bits(a.leaves.positions, b.leaves.positions) &&
         same_bits(a.leaves.length_m, b.leaves.length_m) && same_bits(a.leaves.width_m, b.leaves.width_m) &&
         same_bits(a.leaves.material, b.leaves.material);
}

TEST(TreeMaker, SameSeedSameTreeOtherSeedOtherTree) {
  TreeMakerTemplate t = basic_template();
  t.gravity = 0.08f;
  const TreeModel a = make_treemaker_tree(t, 7), b = make_treemaker_tree(t, 7), c = make_treemaker_tree(t, 8);
  EXPECT_TRUE(same_model(a, b));
  EXPECT_FALSE(same_model(a, c));
  EXPECT_GT(a.stems.size(), 3u);
}

// §V: "the random number generated between 0.4 and 1.6 is truncated", so 0 or 1 branch per
// particle and iteration with probability ½ each; with two iterations only the first branches.
TEST(TreeMaker, BranchCountFollowsTheTruncatedRange) {
  TreeMakerTemplate t = basic_template();
  t.iterations = 2;
  const int trees = 2000;
  int branches = 0;
  for (int s = 0; s < trees; ++s)
    branches += static_cast<int>(make_treemaker_tree(t, static_cast<uint64_t>(s)).stems.size()) - 1;
  const double mean = static_cast<double>(branches) / trees;
  EXPECT_NEAR(mean, 0.5, 4.0 * std::sqrt(0.25 / trees)) << mean;
}

// Triplets are chosen by their probability; the factor scales the growth vector, so a child's one
// segment tells which triplet made it.
TEST(TreeMaker, TripletsAreChosenByProbability) {
  TreeMakerTemplate t = basic_template();
  t.iterations = 2;
  t.particles[0].acc = 0.0f;
  t.particles[0].mag = {20.0f, 20.0f};
  t.branches[0].number = {3.0f, 3.0f};
  t.branches[0].choices = {{0.3f, {45.0f, 45.0f}, {0.0f, 0.0f}, {0.5f, 0.5f}},
                           {0.7f, {45.0f, 45.0f}, {180.0f, 180.0f}, {1.0f, 1.0f}}};
  int small = 0, total = 0;
  for (int s = 0; s < 1000; ++s) {
    const TreeModel m = make_treemaker_tree(t, static_cast<uint64_t>(s));
    ASSERT_EQ(m.stems.size(), 4u);
    const float trunk_segment = m.stems.length_m[0] / 2.0f;
    for (size_t i = 1; i < m.stems.size(); ++i) {
      const float ratio = m.stems.length_m[i] / trunk_segment;
      ASSERT_TRUE(std::abs(ratio - 0.5f) < 1e-3f || std::abs(ratio - 1.0f) < 1e-3f) << ratio;
      small += ratio < 0.75f;
      ++total;
    }
  }
  const double sigma = std::sqrt(total * 0.3 * 0.7);
  EXPECT_NEAR(small, 0.3 * total, 4.0 * sigma);
}

// Figure 1 / §V: dir 0..20 is "0 to 20 degrees above the horizontal on one side", 160..180 the
// other side; angle is measured from the parent limb.
TEST(TreeMaker, BranchAngleAndDirectionAboutTheLimb) {
  TreeMakerTemplate t = basic_template();
  t.iterations = 2;
  t.particles[0].dir = Vec3(1, 0, 0);  // a horizontal parent along +x
  t.branches[0].number = {1.0f, 1.0f};
  for (const float dir : {0.0f, 90.0f, 180.0f}) {
    t.branches[0].choices = {{1.0f, {50.0f, 50.0f}, {dir, dir}, {1.0f, 1.0f}}};
    const TreeModel m = make_treemaker_tree(t, 3);
    ASSERT_EQ(m.stems.size(), 2u);
    const uint32_t f = m.stems.first_section[1];
    const Vec3 d = glm::normalize(m.sections.positions[f + 1] - m.sections.positions[f]);
    EXPECT_NEAR(std::acos(std::clamp(d.x, -1.0f, 1.0f)), radians(50.0f), 1e-4f) << dir;
    if (dir == 90.0f) {
      EXPECT_NEAR(d.z, std::sin(radians(50.0f)), 1e-4f);  // straight up about the limb
    } else {
      EXPECT_NEAR(d.z, 0.0f, 1e-4f) << dir;  // horizontal, on opposite sides
      EXPECT_NEAR(std::abs(d.y), std::sin(radians(50.0f)), 1e-4f);
    }
  }
}

// §II: gravity × cos(angle to the horizontal) comes off the growth vector's z each iteration.
TEST(TreeMaker, GravityBendsHorizontalLimbsDownAndLeavesVerticalOnesStraight) {
  TreeMakerTemplate t = basic_template();
  t.iterations = 10;
  t.branches[0].number = {0.0f, 0.0f};
  t.particles[0].acc = 0.0f;
  t.particles[0].dir = Vec3(1, 0, 0);
  t.gravity = 0.1f;
  const TreeModel m = make_treemaker_tree(t, 1);
  const auto& p = m.sections.positions;
  float previous_slope = 1.0f;
  for (size_t k = 1; k < p.size(); ++k) {
    const Vec3 d = glm::normalize(p[k] - p[k - 1]);
    if (k == 1) {
      EXPECT_NEAR(d.z, 0.0f, 1e-6f);
    } else {
      EXPECT_LT(d.z, previous_slope) << k;  // ever steeper downward
    }
    previous_slope = d.z;
  }
  // One step from horizontal: z = -g, renormalised.
  const Vec3 d2 = glm::normalize(p[2] - p[1]);
  EXPECT_NEAR(d2.z, -0.1f / std::sqrt(1.01f), 1e-5f);

  t.particles[0].dir = Vec3(0, 0, 1);
  const TreeModel up = make_treemaker_tree(t, 1);
  for (const Vec3& q : up.sections.positions) EXPECT_NEAR(std::hypot(q.x, q.y), 0.0f, 1e-5f);

  t.particles[0].dir = Vec3(1, 0, 0);
  t.gravity = 0.0f;
  const TreeModel straight = make_treemaker_tree(t, 1);
  for (const Vec3& q : straight.sections.positions) EXPECT_NEAR(q.z, 0.0f, 1e-6f);
}

// §II: every stored position's width grows by growth= each later iteration, so widths grow with
// age: non-increasing from base to tip, zero at the tip, N·growth at the trunk base.
TEST(TreeMaker, WidthsIncreaseWithAge) {
  TreeMakerTemplate t = basic_template();
  t.iterations = 9;
  const TreeModel m = make_treemaker_tree(t, 5);
  ASSERT_GT(m.stems.size(), 2u);
  EXPECT_NEAR(m.sections.radius_m[0], 0.5f * 9 * 0.4f * t.unit_m, 1e-6f);
  for (size_t s = 0; s < m.stems.size(); ++s) {
    const uint32_t f = m.stems.first_section[s], n = m.stems.section_count[s];
    EXPECT_EQ(m.sections.radius_m[f + n - 1], 0.0f);
    for (uint32_t k = 1; k < n; ++k) EXPECT_LE(m.sections.radius_m[f + k], m.sections.radius_m[f + k - 1]);
    if (m.stems.parent[s] >= 0) {
      const uint32_t pf = m.stems.first_section[static_cast<size_t>(m.stems.parent[s])];
      EXPECT_LT(m.sections.radius_m[f], m.sections.radius_m[pf]);  // thinner than the parent's base
    }
  }
  // A negative age slows the lateral growth: the base saturates at Σ max(0, 0.4 − 0.1k) = 1.0.
  t.particles[0].age = -0.1f;
  const TreeModel aged = make_treemaker_tree(t, 5);
  EXPECT_NEAR(aged.sections.radius_m[0], 0.5f * 1.0f * t.unit_m, 1e-6f);
  EXPECT_NEAR(aged.sections.radius_m[1], 0.5f * 1.0f * t.unit_m, 1e-6f);
}

// §II: "the program adds a leaf to the end of every branch"; the definition is chosen by its p.
TEST(TreeMaker, OneLeafDefinitionAtEveryBranchEnd) {
  TreeMakerTemplate t = basic_template();
  t.iterations = 8;
  t.gravity = 0.05f;
  TreeMakerLeaf flower;  // a right triangle (one quad) and a line (one quad)
  flower.p = 0.3f;
  flower.coord = TreeMakerCoord::Limb;
  flower.out_deg = 20.0f;
  flower.up_deg = 20.0f;
  flower.elements = {{{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 2)}, 2, {0.9f, 1.0f}},
                     {{Vec3(0, 0, 0), Vec3(0, 1, 1)}, 1, {0.5f, 0.5f}}};
  t.leaves[0].p = 0.7f;  // a general triangle: two quads
  t.leaves.push_back(flower);
  int stems = 0, flowers = 0;
  for (uint64_t seed = 0; seed < 40; ++seed) {
    const TreeModel m = make_treemaker_tree(t, seed);
    std::map<int32_t, std::vector<size_t>> by_stem;
    for (size_t i = 0; i < m.leaves.size(); ++i) by_stem[m.leaves.stem[i]].push_back(i);
    ASSERT_EQ(by_stem.size(), m.stems.size());
    for (const auto& [stem, quads] : by_stem) {
      ASSERT_EQ(quads.size(), 2u) << stem;
      const uint32_t tip =
          m.stems.first_section[static_cast<size_t>(stem)] + m.stems.section_count[static_cast<size_t>(stem)] - 1;
      const bool is_flower = m.leaves.shapes[quads[1]] == LeafShape::Rectangle;
      flowers += is_flower;
      for (const size_t q : quads) {
        // Within the element's reach (template extent ≤ 9.5 units) of the branch end.
        EXPECT_LT(glm::length(m.leaves.positions[q] - m.sections.positions[tip]), 9.5f * t.unit_m);
        EXPECT_EQ(m.leaves.material[q], is_flower && q == quads[0] ? 1 : 0);
      }
    }
    stems += static_cast<int>(m.stems.size());
  }
  EXPECT_NEAR(flowers, 0.3 * stems, 4.0 * std::sqrt(stems * 0.21));
}

// A tri= element becomes right-triangle quads covering exactly the triangle; in leaf coordinates
// with no deviation the element's y axis is the world's up.
TEST(TreeMaker, TrianglesBecomeRightTriangleQuadsOfTheSameArea) {
  TreeMakerTemplate t = basic_template();
  t.iterations = 1;
  t.leaves[0].elements = {{{Vec3(0, 0, 0), Vec3(3, 1, -1), Vec3(3, 1, 1)}, 1, {1, 1}},
                          {{Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, 0, 2)}, 1, {1, 1}}};
  const TreeModel m = make_treemaker_tree(t, 2);
  ASSERT_EQ(m.leaves.size(), 4u);
  const float u2 = t.unit_m * t.unit_m;
  const float area1 = 0.5f * glm::length(glm::cross(Vec3(3, 1, -1), Vec3(3, 1, 1))) * u2;
  const float area2 = 0.5f * glm::length(glm::cross(Vec3(2, 0, 0), Vec3(1, 0, 3))) * u2;
  EXPECT_NEAR(0.5f * (m.leaves.length_m[0] * m.leaves.width_m[0] + m.leaves.length_m[1] * m.leaves.width_m[1]), area1,
              1e-4f * area1);
  EXPECT_NEAR(0.5f * (m.leaves.length_m[2] * m.leaves.width_m[2] + m.leaves.length_m[3] * m.leaves.width_m[3]), area2,
              1e-4f * area2);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(m.leaves.shapes[i], LeafShape::RightTriangle);
  // The flat centre triangle (y = 0 in leaf coordinates) lies horizontal, its upper side up.
  EXPECT_NEAR(m.leaves.frames[2].y.z, 1.0f, 1e-5f);
  EXPECT_NEAR(m.leaves.frames[3].y.z, 1.0f, 1e-5f);
  // The mesher's quad corners reproduce the triangle's vertices.
  const TreeMesh mesh = make_tree_mesh(m);
  const Vec3 tip = m.sections.positions.back();
  std::set<std::tuple<int, int, int>> corners;
  for (size_t q = 2; q < 4; ++q)
    for (const size_t k : {0, 1, 3}) {
      const Vec3 c = (mesh.leaves.corners[4 * q + k] - tip) / t.unit_m;
      corners.insert({static_cast<int>(std::lround(c.x * 1000)), static_cast<int>(std::lround(c.y * 1000)),
                      static_cast<int>(std::lround(c.z * 1000))});
    }
  // Four distinct points: the triangle's three vertices and the foot of its altitude.
  EXPECT_EQ(corners.size(), 4u);
}

TEST(TreeMaker, MaterialsFollowTheElementColours) {
  TreeMakerTemplate t = basic_template();
  TreeMakerLeaf flower;
  flower.p = 0.4f;
  flower.elements = {{{Vec3(0, 0, 0), Vec3(3, 1, -1), Vec3(3, 1, 1)}, 2, {0.9f, 1.0f}},
                     {{Vec3(-1, 1, -1), Vec3(1, 1, -1), Vec3(0, 1, 2)}, 1, {0.5f, 0.8f}}};
  t.leaves[0].p = 0.6f;
  t.leaves.push_back(flower);
  const TreeMakerMaterials mats = treemaker_materials(t);
  ASSERT_EQ(mats.element_rgb.size(), 2u);
  EXPECT_EQ(mats.element_color_names[0], "green");
  EXPECT_EQ(mats.element_color_names[1], "white");
  EXPECT_NEAR(mats.element_rgb[0].y, 0.5f * (0.6f + 0.65f), 1e-6f);  // mean of 0.4–0.8 and 0.5–0.8
  EXPECT_EQ(mats.element_rgb[0].x, 0.0f);
  EXPECT_NEAR(mats.element_rgb[1].x, 0.95f, 1e-6f);
  EXPECT_NEAR(mats.bark_rgb.x, 0.35f, 1e-6f);
  EXPECT_NEAR(mats.bark_rgb.y, 0.9f * 0.35f, 1e-6f);
}

TEST(TreeMaker, RunawayBranchingIsAClearError) {
  TreeMakerTemplate t = basic_template();
  t.iterations = 40;
  t.particles[0].acc = 0.0f;
  t.branches[0].number = {4.0f, 5.0f};
  t.branches[0].choices[0].factor = {1.0f, 1.0f};
  try {
    make_treemaker_tree(t, 1);
    FAIL() << "4^40 particles were grown";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tree too large"), std::string::npos) << e.what();
  }
}

TEST(TreeMaker, InvalidTemplatesBuiltInCodeAreClearErrors) {
  TreeMakerTemplate t = basic_template();
  t.leaves[0].elements[0].color = 7;
  EXPECT_THROW(make_treemaker_tree(t, 1), Error);
  EXPECT_THROW(treemaker_materials(t), Error);
  t = basic_template();
  t.leaves[0].elements[0].points.pop_back();
  t.leaves[0].elements[0].points.pop_back();
  EXPECT_THROW(make_treemaker_tree(t, 1), Error);
}

TEST(TreeMaker, ShrinkingGrowthStopsAParticle) {
  TreeMakerTemplate t = basic_template();
  t.iterations = 30;
  t.branches[0].number = {0.0f, 0.0f};
  t.particles[0].mag = {5.0f, 5.0f};
  t.particles[0].acc = -1.0f;  // 5, 4, 3, 2, 1 then stopped
  const TreeModel m = make_treemaker_tree(t, 1);
  ASSERT_EQ(m.stems.size(), 1u);
  EXPECT_EQ(m.stems.section_count[0], 6u);
  EXPECT_NEAR(m.stems.length_m[0], 15.0f * t.unit_m, 1e-5f);
}

}  // namespace
}  // namespace sylva
