// Arbaro's own species files (tests/data/arbaro, GPL test inputs), generated under Arbaro's
// reading: stem and leaf counts per level against figures derived from Arbaro's algorithm
// (StemImpl.prepareSubstemParams, makeSubstems, makeLeaves) where it is deterministic.

#include "geometry/trees/tree_mesher.h"
#include "scenes/species.h"

#include "geometry/trees/tree_stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

namespace sylva {
namespace {

const std::filesystem::path kArbaro = std::filesystem::path(SYLVA_SOURCE_DIR) / "tests" / "data" / "arbaro";

// Children and leaves carried by each stem.
struct PerStem {
  std::vector<int> children, leaves;
};
PerStem per_stem(const TreeModel& m) {
  PerStem c{std::vector<int>(m.stems.size(), 0), std::vector<int>(m.stems.size(), 0)};
  for (size_t i = 0; i < m.stems.size(); ++i)
    if (m.stems.parent[i] >= 0) ++c.children[static_cast<size_t>(m.stems.parent[i])];
  for (const int32_t s : m.leaves.stem) ++c.leaves[static_cast<size_t>(s)];
  return c;
}

TEST(ArbaroSpecies, TamarackCountsFollowArbarosFormulas) {
  // No splits at any level (0BaseSplits = nSegSplits = 0), Shape 0, no length variation.
  const Species s = load_species(kArbaro / "tamarack.xml");
  ASSERT_EQ(std::get<WeberPennParams>(s.model).reading, wp::Reading::Arbaro);
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const TreeModel m = make_species_model(s, seed);
    const std::vector<int> n = count_stems_per_level(m);
    ASSERT_EQ(n.size(), 3u);
    EXPECT_EQ(n[0], 1);
    EXPECT_NEAR(n[1], 75, 1);  // 1Branches over the trunk above BaseSize
    // Level 2: each level-1 stem gets (int)(2Branches·(0.2 + 0.8·length/length_parent/1Length))
    // children; with Arbaro's ShapeRatio(0, r) = r, length/length_parent/1Length = r, the stem's
    // position ratio (length_trunk − offset)/(length_trunk − length_base).
    const PerStem c = per_stem(m);
    const float trunk = m.stems.length_m[0];
    int expected2 = 0;
    for (size_t i = 0; i < m.stems.size(); ++i) {
      if (m.stems.level[i] != 1) continue;
      const float ratio = m.stems.length_m[i] / trunk / 0.4f;
      const int want = static_cast<int>(std::floor(50.0f * (0.2f + 0.8f * ratio) + 1e-4f));
      expected2 += want;
      // The topmost stems are a few centimetres long; their children are thinner than the smallest
      // stem formed (20 µm), so they are left out of the per-stem check.
      if (m.stems.length_m[i] < 0.02f * trunk) continue;
      EXPECT_NEAR(c.children[i], want, 1) << "stem " << i;
    }
    EXPECT_NEAR(n[2], expected2, 0.01 * expected2);
    // The same total from the evenly spread positions alone (r_j = (j + ½)/75), as Arbaro places them.
    int spread = 0;
    for (int j = 0; j < 75; ++j) spread += static_cast<int>(50.0f * (0.2f + 0.8f * (j + 0.5f) / 75.0f));
    EXPECT_NEAR(n[2], spread, 0.03 * spread);
    // Leaves: Leaves·ShapeRatio(4, offset/length_parent) = 50·(0.5 + 0.5·offset/length_parent) per stem.
    for (size_t i = 0; i < m.stems.size(); ++i) {
      if (m.stems.level[i] != 2) continue;
      const float parent = m.stems.length_m[static_cast<size_t>(m.stems.parent[i])];
      EXPECT_NEAR(c.leaves[i], 50.0f * (0.5f + 0.5f * m.stems.offset_m[i] / parent), 1.01f) << "stem " << i;
    }
  }
}

TEST(ArbaroSpecies, CottonwoodCountsFollowArbarosFormulas) {
  // 0BaseSplits = 3: four trunk stems sharing 1Branches; Shape 3, so every level-1 stem has
  // length/length_parent/1Length = 1 and (int)(30·(0.2 + 0.8)) = 30 children.
  const Species s = load_species(kArbaro / "eastern_cottonwood.xml");
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const TreeModel m = make_species_model(s, seed);
    const std::vector<int> n = count_stems_per_level(m);
    ASSERT_EQ(n.size(), 3u);
    EXPECT_EQ(n[0], 4);
    EXPECT_NEAR(n[1], 40, 2);
    const PerStem c = per_stem(m);
    for (size_t i = 0; i < m.stems.size(); ++i) {
      if (m.stems.level[i] == 1) {
        EXPECT_NEAR(c.children[i], 30, 1) << "stem " << i;
      }
    }
    EXPECT_NEAR(n[2], 30 * n[1], n[1]);
  }
}

TEST(ArbaroSpecies, WillowLeavesPerShootAndGround) {
  // LeafDistrib 3 (cylindrical): every level-3 shoot carries Leaves = 10, clones included.
  const Species s = load_species(kArbaro / "weeping_willow.xml");
  const TreeModel m = make_species_model(s, 1);
  const std::vector<int> n = count_stems_per_level(m);
  ASSERT_EQ(n.size(), 4u);
  EXPECT_GE(n[0], 3);  // 0BaseSplits = 2
  const PerStem c = per_stem(m);
  int shoots = 0;
  for (size_t i = 0; i < m.stems.size(); ++i) {
    if (m.stems.level[i] != 3) continue;
    ++shoots;
    EXPECT_NEAR(c.leaves[i], 10, 1) << "stem " << i;
  }
  EXPECT_GT(shoots, 1000);
  const TreeMesh mesh = make_tree_mesh(m, {});
  for (const Vec3& q : mesh.stems.positions) ASSERT_GE(q.z, -1e-4f);
  for (const Vec3& q : mesh.leaves.corners) ASSERT_GE(q.z, -1e-4f);
}

}  // namespace
}  // namespace sylva
