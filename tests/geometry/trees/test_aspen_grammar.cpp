// The aspen grammar (seed 002 Ch. 6): determinism, and the invariants its semantic routines
// promise — divergence ≈ 138°, diameter contraction (6.13) and the area rule at forks (6.8),
// length contraction (6.12) with its self-adjustment minimum, branch angles (6.14) never below
// the minimum and falling with the child number, no trunk branches before the fifth point,
// lifting, dead branches, leaf clusters at living tips.

#include "core/error.h"
#include "geometry/trees/lsystem/aspen_grammar.h"
#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/tree_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

namespace sylva {
namespace {

struct Grown {
  TreeModel model;
  AspenGrammarTrace trace;
};

Grown grow(uint64_t seed, const AspenGrammarParams& p = {}) {
  Grown g;
  g.model = make_aspen_grammar_tree(p, seed, &g.trace);
  return g;
}

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(AspenGrammar, SameSeedSameTreeOtherSeedOtherTree) {
  const TreeModel a = make_aspen_grammar_tree({}, 7), b = make_aspen_grammar_tree({}, 7);
  EXPECT_TRUE(same_bits(a.sections.positions, b.sections.positions));
  EXPECT_TRUE(same_bits(a.sections.radius_m, b.sections.radius_m));
  EXPECT_TRUE(same_bits(a.leaves.positions, b.leaves.positions));
  EXPECT_TRUE(same_bits(a.stems.dead, b.stems.dead));
  // Tracing does not change the tree.
  EXPECT_TRUE(same_bits(grow(7).model.sections.positions, a.sections.positions));
  std::set<size_t> stem_counts;
  for (const uint64_t seed : {1u, 2u, 3u}) {
    const TreeModel m = make_aspen_grammar_tree({}, seed);
    EXPECT_FALSE(same_bits(m.sections.positions, a.sections.positions));
    stem_counts.insert(m.stems.size());
  }
  EXPECT_EQ(stem_counts.size(), 3u);
}

TEST(AspenGrammar, DivergenceAnglesAverage138Degrees) {
  const AspenGrammarParams p;
  double sum = 0;
  int n = 0;
  for (const uint64_t seed : {1u, 2u, 3u, 4u})
    for (const AspenChildRecord& c : grow(seed).trace.children) {
      if (c.fork || c.child_number < 2) continue;
      EXPECT_GE(c.divergence_step_deg, p.divergence_deg - p.divergence_noise_deg);
      EXPECT_LE(c.divergence_step_deg, p.divergence_deg + p.divergence_noise_deg);
      sum += c.divergence_step_deg;
      ++n;
    }
  ASSERT_GT(n, 500);
  const double sd = p.divergence_noise_deg / std::sqrt(3.0);  // uniform ± noise
  EXPECT_NEAR(sum / n, 138.0, 4.0 * sd / std::sqrt(n));
}

TEST(AspenGrammar, DiameterContractionAndAreaRule) {
  const AspenGrammarParams p;
  double sum = 0;
  int n = 0, forks = 0;
  for (const uint64_t seed : {1u, 2u, 3u}) {
    const Grown g = grow(seed);
    for (size_t i = 0; i < g.trace.children.size(); ++i) {
      const AspenChildRecord& c = g.trace.children[i];
      if (c.fork) {
        // The two children of a fork are consecutive records; their areas add up (eq. 6.8).
        if (i + 1 < g.trace.children.size() && g.trace.children[i + 1].fork &&
            g.trace.children[i + 1].parent == c.parent) {
          const float r2 = c.diameter_ratio, s2 = g.trace.children[i + 1].diameter_ratio;
          EXPECT_NEAR(r2 * r2 + s2 * s2, 1.0f, 1e-5f);
          ++forks;
          ++i;
        }
        continue;
      }
      EXPECT_GE(c.diameter_ratio, 1.0f - p.diameter_contraction_max - 1e-6f);
      EXPECT_LE(c.diameter_ratio, 1.0f - p.diameter_contraction_min + 1e-6f);
      sum += c.diameter_ratio;
      ++n;
      // The record matches the model: the child's root radius over the parent's at the branch point.
      const size_t stem = static_cast<size_t>(c.stem);
      EXPECT_NEAR(g.model.stems.base_radius_m[stem], g.model.sections.radius_m[g.model.stems.first_section[stem]],
                  1e-7f);
    }
  }
  EXPECT_GT(forks, 5);
  const double mean = 1.0 - 0.5 * (p.diameter_contraction_min + p.diameter_contraction_max);
  const double sd = (p.diameter_contraction_max - p.diameter_contraction_min) / std::sqrt(12.0);
  EXPECT_NEAR(sum / n, mean, 4.0 * sd / std::sqrt(n));
}

TEST(AspenGrammar, SelfAdjustmentBoundsAnglesAndLengths) {
  const AspenGrammarParams p;
  const Grown g = grow(5);
  const TreeModel& m = g.model;
  for (const AspenChildRecord& c : g.trace.children) {
    const size_t stem = static_cast<size_t>(c.stem);
    EXPECT_GE(c.length, p.min_length);
    EXPECT_NEAR(m.stems.length_m[stem], c.length * p.unit_m, 1e-4f);
    EXPECT_GE(c.branch_angle_rad, p.min_branch_angle_rad);
    // The geometry agrees: the child's root direction against the parent's at the branch point.
    const size_t parent = static_cast<size_t>(c.parent);
    const uint32_t first = m.stems.first_section[parent];
    const Vec3 base = m.sections.positions[m.stems.first_section[stem]];
    uint32_t at = first;
    for (uint32_t k = first; k < first + m.stems.section_count[parent]; ++k)
      if (m.sections.positions[k] == base) at = k;
    ASSERT_EQ(m.sections.positions[at], base);
    // The trunk's direction is its vertical axis (its bumps offset points, they do not turn it).
    const Vec3 parent_dir = parent == 0 ? Vec3(0, 0, 1) : m.sections.frames[at].z;
    const float angle = safe_acos(glm::dot(parent_dir, m.sections.frames[m.stems.first_section[stem]].z));
    EXPECT_NEAR(angle, c.branch_angle_rad, 2e-3f);
    if (!c.fork && !c.dead) {
      // Eq. 6.12: golden-ratio contraction minus the child-number and generation terms, or the
      // self-adjusted minimum.
      EXPECT_LE(c.length, std::max(p.length_ratio * m.stems.length_m[parent] / p.unit_m -
                                       p.length_child_term * static_cast<float>(c.child_number) -
                                       p.length_generation_term * static_cast<float>(c.generation),
                                   p.min_length) +
                              1e-3f);
    }
    if (!c.fork) {
      // Eq. 6.14: the angle falls with the child number.
      EXPECT_NEAR(c.branch_angle_rad,
                  std::max(radians(p.branch_angle_base_deg) - p.branch_angle_child_rad * c.child_number -
                               p.branch_angle_generation_rad * c.generation,
                           p.min_branch_angle_rad),
                  1e-5f);
    }
  }
  // Lifting: no branch segment points further down than the droop limit.
  for (size_t s = 1; s < m.stems.size(); ++s)
    for (uint32_t k = 1; k < m.stems.section_count[s]; ++k)
      EXPECT_GE(m.sections.frames[m.stems.first_section[s] + k].z.z, p.droop_limit - 1e-5f);
}

TEST(AspenGrammar, TrunkBranchesStartAtTheFifthPoint) {
  const AspenGrammarParams p;
  const TreeModel m = grow(2).model;
  const float fifth = m.sections.arc_m[static_cast<size_t>(p.first_trunk_point)];
  int on_trunk = 0;
  for (size_t s = 1; s < m.stems.size(); ++s)
    if (m.stems.parent[s] == 0) {
      EXPECT_GE(m.stems.offset_m[s], fifth - 1e-5f);
      ++on_trunk;
    }
  EXPECT_GT(on_trunk, 10);
  // The trunk reaches about the given height and tapers by the trunk shrinkage (6.9, 6.10).
  const uint32_t last = m.stems.section_count[0] - 1;
  EXPECT_NEAR(m.sections.positions[last].z, p.height * p.unit_m, 0.1f * p.height * p.unit_m);
  EXPECT_NEAR(m.sections.radius_m[last], 0.5f * p.diameter * p.unit_m * (1 - p.trunk_shrinkage), 1e-6f);
}

TEST(AspenGrammar, DeadBranchesAreShortBareAndChildless) {
  const AspenGrammarParams p;
  const Grown g = grow(3);
  const TreeModel& m = g.model;
  ASSERT_EQ(m.stems.dead.size(), m.stems.size());
  std::vector<int> children(m.stems.size(), 0), leaves(m.stems.size(), 0);
  for (size_t s = 1; s < m.stems.size(); ++s) ++children[static_cast<size_t>(m.stems.parent[s])];
  for (const int s : m.leaves.stem) ++leaves[static_cast<size_t>(s)];
  int dead = 0;
  for (const AspenChildRecord& c : g.trace.children) {
    const size_t s = static_cast<size_t>(c.stem);
    EXPECT_EQ(m.stems.is_dead(s), c.dead);
    if (!c.dead) continue;
    ++dead;
    EXPECT_EQ(children[s], 0);
    EXPECT_EQ(leaves[s], 0);
    EXPECT_LE(c.length,
              std::max(p.dead_length * p.length_ratio * m.stems.length_m[static_cast<size_t>(c.parent)] / p.unit_m,
                       p.min_length));
  }
  EXPECT_GT(dead, 5);
  // Living tips carry a leaf cluster each.
  int tips = 0;
  for (size_t s = 1; s < m.stems.size(); ++s)
    if (!m.stems.is_dead(s) && leaves[s] > 0) {
      EXPECT_EQ(leaves[s], p.leaves_per_cluster);
      ++tips;
    }
  EXPECT_GT(tips, 100);
  EXPECT_EQ(leaves[0], p.leaves_per_cluster);  // the leader's tip
}

TEST(AspenGrammar, DeadStemsMeshApartOnlyWhenAsked) {
  const TreeModel m = make_aspen_grammar_tree({}, 3);
  TreeMeshOptions split;
  split.split_dead_stems = true;
  const TreeMesh one = make_tree_mesh(m), two = make_tree_mesh(m, split);
  EXPECT_TRUE(one.dead_stems.triangles.empty());
  ASSERT_FALSE(two.dead_stems.triangles.empty());
  EXPECT_EQ(two.stems.triangles.size() + two.dead_stems.triangles.size(), one.stems.triangles.size());
  // Every dead-mesh vertex lies on a dead stem: a ring vertex at a section's radius from it, a cap
  // or tip vertex on it (the grammar's stems have no lobes).
  const StemSections& sec = m.sections;
  for (const Vec3& q : two.dead_stems.positions) {
    float best = std::numeric_limits<float>::infinity();
    for (size_t s = 0; s < m.stems.size(); ++s) {
      if (!m.stems.is_dead(s)) continue;
      for (uint32_t k = 0; k < m.stems.section_count[s]; ++k) {
        const uint32_t i = m.stems.first_section[s] + k;
        best = std::min(best, glm::length(q - sec.positions[i]) - sec.radius_m[i]);
      }
    }
    ASSERT_LE(best, 1e-3f);
  }
  // A tree without dead stems meshes identically (same hash) with or without the split.
  TreeModel alive = m;
  std::fill(alive.stems.dead.begin(), alive.stems.dead.end(), uint8_t{0});
  EXPECT_EQ(hash_tree_mesh(make_tree_mesh(alive, split)), hash_tree_mesh(make_tree_mesh(alive)));
  EXPECT_NE(hash_tree_mesh(two), hash_tree_mesh(one));
}

TEST(AspenGrammar, MeshesIntoTubesAndRejectsRunawayTrees) {
  const TreeModel m = make_aspen_grammar_tree({}, 1);
  TreeMeshOptions eight;
  eight.radial_segments = {8, 8, 8, 8};  // the thesis's 8-point circles
  const TreeMesh mesh = make_tree_mesh(m, eight);
  EXPECT_GT(mesh.stems.triangles.size(), 1000u);
  EXPECT_EQ(mesh.leaves.size(), m.leaves.size());
  AspenGrammarParams huge;
  huge.generations = 8;
  huge.height = 1e5f;
  huge.min_length = 1e-3f;
  huge.length_child_term = 0;
  huge.length_generation_term = 0;
  huge.branch_probability = 1;
  huge.dead_probability = 0;
  EXPECT_THROW(make_aspen_grammar_tree(huge, 1), Error);
}

}  // namespace
}  // namespace sylva
