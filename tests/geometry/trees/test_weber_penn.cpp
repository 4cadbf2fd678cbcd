// The Weber & Penn generator (geometry/trees/weber_penn/weber_penn.h): formulas as they show in whole trees, and
// invariants of the generated structure.

#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/weber_penn/weber_penn.h"
#include "geometry/trees/weber_penn/weber_penn_shape.h"
#include "tests/geometry/trees/wp_test_species.h"

#include "geometry/trees/tree_stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>

namespace sylva {
namespace {

float angle_deg(const Vec3& a, const Vec3& b) {
  return degrees(safe_acos(glm::dot(glm::normalize(a), glm::normalize(b))));
}

// A bare trunk: one level, straight unless the test curves it.
WeberPennParams bare_trunk() {
  WeberPennParams p;
  p.levels = 1;
  p.scale = 10.0f;
  p.flare = 0.0f;
  p.leaves = 0;
  p.level[0].curve_res = 10;
  return p;
}

Vec3 last_direction(const TreeModel& m, size_t stem) {
  return m.sections.frames[m.stems.first_section[stem] + m.stems.section_count[stem] - 1].z;
}
Vec3 first_direction(const TreeModel& m, size_t stem) { return m.sections.frames[m.stems.first_section[stem]].z; }

TEST(WeberPenn, CurvedStemBendsFromItsSecondSegment) {
  // The first segment keeps the stem's direction; each later one turns by nCurve/nCurveRes.
  for (const float curve : {40.0f, -25.0f, 90.0f}) {
    WeberPennParams p = bare_trunk();
    p.level[0].curve = curve;
    const TreeModel m = make_weber_penn_tree(p, 3);
    ASSERT_EQ(m.stems.size(), 1u);
    EXPECT_NEAR(angle_deg(first_direction(m, 0), Vec3(0, 0, 1)), 0.0f, 1e-3f);
    EXPECT_NEAR(angle_deg(m.sections.frames[1].z, Vec3(0, 0, 1)), 0.0f, 1e-3f);  // end of segment 0
    EXPECT_NEAR(angle_deg(first_direction(m, 0), last_direction(m, 0)), std::abs(curve) * 0.9f, 1e-2f) << curve;
    EXPECT_NEAR(m.stems.length_m[0], 10.0f, 1e-5f);
  }
  // CurveBack: segment 1 (first half) turns 2·nCurve/nCurveRes, segments 2 and 3 back by
  // 2·nCurveBack/nCurveRes each.
  WeberPennParams p = bare_trunk();
  p.level[0].curve_res = 4;
  p.level[0].curve = 30.0f;
  p.level[0].curve_back = -30.0f;
  const TreeModel m = make_weber_penn_tree(p, 3);
  EXPECT_NEAR(angle_deg(first_direction(m, 0), m.sections.frames[2].z), 15.0f, 1e-2f);  // after 2 segments
  EXPECT_NEAR(angle_deg(first_direction(m, 0), last_direction(m, 0)), 15.0f, 1e-2f);
}

TEST(WeberPenn, CurveVariationAndHelix) {
  WeberPennParams p = bare_trunk();
  p.level[0].curve_v = 20.0f;  // ± 2° per segment about x: the total bend stays within ±20°
  const TreeModel m = make_weber_penn_tree(p, 5);
  EXPECT_LE(angle_deg(first_direction(m, 0), last_direction(m, 0)), 20.0f + 1e-3f);
  EXPECT_GT(angle_deg(first_direction(m, 0), last_direction(m, 0)), 0.0f);
  // Negative nCurveV: a helix; every segment declines |nCurveV| from the stem's axis.
  p.level[0].curve_v = -30.0f;
  const TreeModel h = make_weber_penn_tree(p, 5);
  for (uint32_t k = 1; k < h.stems.section_count[0]; ++k)
    EXPECT_NEAR(angle_deg(h.sections.frames[k].z, Vec3(0, 0, 1)), 30.0f, 1e-2f);
  EXPECT_NEAR(glm::length(Vec2(h.sections.positions.back())), 0.0f, 0.05f);  // a full turn returns
}

// Trunk vertical and straight, BaseSize 0.5, one vertical level-1 stem, horizontal level-2 stems
// whose y axis points up (DownAngle 90).
WeberPennParams attraction_tree(float attraction_up) {
  WeberPennParams p = bare_trunk();
  p.levels = 3;
  p.base_size = 0.5f;
  p.shape = 3;  // cylindrical: the level-1 stem has its full length and 8 children
  p.level[0].curve_res = 1;
  p.level[1] = {};
  p.level[1].length = 0.5f;
  p.level[1].curve_res = 1;
  p.level[1].down_angle = 0.0f;
  p.level[1].branches = 1;
  p.level[2] = {};
  p.level[2].length = 0.5f;
  p.level[2].curve_res = 10;
  p.level[2].down_angle = 90.0f;
  p.level[2].branches = 8;
  p.attraction_up = attraction_up;
  return p;
}

TEST(WeberPenn, AttractionUpTurnsHorizontalStemTowardVertical) {
  const TreeModel flat = make_weber_penn_tree(attraction_tree(0.0f), 9);
  const TreeModel up = make_weber_penn_tree(attraction_tree(1.0f), 9);
  const TreeModel down = make_weber_penn_tree(attraction_tree(-1.0f), 9);
  int level2 = 0;
  for (size_t i = 0; i < up.stems.size(); ++i) {
    if (up.stems.level[i] != 2) continue;
    ++level2;
    EXPECT_NEAR(first_direction(up, i).z, 0.0f, 1e-4f);
    EXPECT_NEAR(last_direction(flat, i).z, 0.0f, 1e-4f);
    // §4.8: each segment after the first turns up by declination·sin(declination)/10.
    float decl = kPi / 2.0f;
    for (int k = 1; k < 10; ++k) decl -= decl * std::sin(decl) / 10.0f;
    EXPECT_NEAR(angle_deg(last_direction(up, i), Vec3(0, 0, 1)), degrees(decl), 0.05f);
    EXPECT_LT(degrees(decl), 45.0f);
    EXPECT_GT(angle_deg(last_direction(down, i), Vec3(0, 0, 1)), 140.0f);
  }
  EXPECT_GE(level2, 7);
}

TEST(WeberPenn, StemCountsLengthsAndDownAngles) {
  // Black Tupelo with a straight trunk and fixed size: level-1 count, lengths and the negative
  // 1DownAngleV mode (angled up near the crown, down near the base).
  WeberPennParams p = test::black_tupelo();
  p.scale_v = 0.0f;
  p.level[0].curve_v = 0.0f;
  p.level[1].length_v = 0.0f;
  p.levels = 2;
  p.leaves = 0;
  const TreeModel m = make_weber_penn_tree(p, 11);
  const float length_trunk = 23.0f, length_base = 0.2f * 23.0f;
  int level1 = 0;
  for (size_t i = 0; i < m.stems.size(); ++i) {
    if (m.stems.level[i] != 1) continue;
    ++level1;
    const float offset = m.stems.offset_m[i];
    const float ratio = (length_trunk - offset) / (length_trunk - length_base);
    EXPECT_GE(offset, length_base);
    EXPECT_NEAR(m.stems.length_m[i], length_trunk * 0.3f * (0.5f + 0.5f * ratio), 1e-3f);  // Shape 4
    const float down = 60.0f - 40.0f * (1.0f - 2.0f * (0.2f + 0.8f * ratio));
    EXPECT_NEAR(angle_deg(first_direction(m, i), Vec3(0, 0, 1)), down, 1e-2f);
  }
  EXPECT_GE(level1, 49);  // 1Branches = 50 spread over the trunk above BaseSize
  EXPECT_LE(level1, 50);
}

TEST(WeberPenn, RotateAnglesSpiralAndAlternate) {
  WeberPennParams p = test::quaking_aspen();
  p.levels = 2;
  p.leaves = 0;
  p.level[0].curve_v = 0.0f;
  const TreeModel m = make_weber_penn_tree(p, 4);
  std::vector<float> azimuth;
  for (size_t i = 0; i < m.stems.size(); ++i)
    if (m.stems.level[i] == 1) azimuth.push_back(degrees(std::atan2(first_direction(m, i).y, first_direction(m, i).x)));
  ASSERT_GT(azimuth.size(), 10u);
  for (size_t k = 1; k < azimuth.size(); ++k)
    EXPECT_NEAR(std::remainder(azimuth[k] - azimuth[k - 1] - 140.0f, 360.0f), 0.0f, 1e-2f);
  // Negative nRotate: alternate sides at ±(180 + nRotate) from the parent's y axis.
  p.level[1].rotate = -120.0f;
  const TreeModel a = make_weber_penn_tree(p, 4);
  azimuth.clear();
  for (size_t i = 0; i < a.stems.size(); ++i)
    if (a.stems.level[i] == 1) azimuth.push_back(degrees(std::atan2(first_direction(a, i).y, first_direction(a, i).x)));
  for (size_t k = 2; k < azimuth.size(); ++k) {
    EXPECT_NEAR(std::remainder(azimuth[k] - azimuth[k - 2], 360.0f), 0.0f, 1e-2f);
    EXPECT_NEAR(std::abs(std::remainder(azimuth[k] - azimuth[k - 1], 360.0f)), 120.0f, 1e-2f);
  }
}

TEST(WeberPenn, SplitCountAveragesSegSplits) {
  // Level-1 stems with two segments have one chance to split; clones never split again.
  WeberPennParams p = test::quaking_aspen();
  p.levels = 2;
  p.leaves = 0;
  p.level[1].branches = 200;
  p.level[1].curve_res = 2;
  p.level[1].seg_splits = 0.3f;
  p.level[1].split_angle = 20.0f;
  const TreeModel m = make_weber_penn_tree(p, 2);
  int originals = 0, clones = 0;
  for (size_t i = 0; i < m.stems.size(); ++i) {
    if (m.stems.level[i] != 1) continue;
    (m.stems.is_clone(i) ? clones : originals)++;
    if (m.stems.is_clone(i)) {
      const size_t twin = static_cast<size_t>(m.stems.clone_of[i]);
      EXPECT_EQ(m.stems.level[twin], 1);
      EXPECT_EQ(m.stems.length_m[twin], m.stems.length_m[i]);
      // The clone starts at its twin's split point.
      EXPECT_EQ(m.sections.positions[m.stems.first_section[i]], m.sections.positions[m.stems.first_section[twin] + 1]);
    }
  }
  ASSERT_GE(originals, 190);
  EXPECT_NEAR(static_cast<double>(clones), 0.3 * originals, 1.0);
}

TEST(WeberPenn, BaseSplitsSpreadEvenly) {
  WeberPennParams p = bare_trunk();
  p.base_splits = 2;
  p.level[0].split_angle = 20.0f;
  p.level[0].curve_res = 4;
  const TreeModel m = make_weber_penn_tree(p, 1);
  ASSERT_EQ(m.stems.size(), 3u);
  std::vector<float> az;
  for (size_t i = 0; i < 3; ++i) {
    const Vec3 d = m.sections.frames[m.stems.first_section[i] + (i == 0 ? 2 : 1)].z;  // segment after the split
    EXPECT_NEAR(angle_deg(d, Vec3(0, 0, 1)), 20.0f * 2.0f / 3.0f, 0.05f);             // 20°, then −20/3 corrected
    az.push_back(degrees(std::atan2(d.y, d.x)));
  }
  EXPECT_NEAR(std::abs(std::remainder(az[1] - az[0], 360.0f)), 120.0f, 0.05f);
  EXPECT_NEAR(std::abs(std::remainder(az[2] - az[0], 360.0f)), 120.0f, 0.05f);
  // The deflection is distributed back: the stems end parallel to the trunk's original direction.
  for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(angle_deg(last_direction(m, i), Vec3(0, 0, 1)), 0.0f, 0.05f);
}

TEST(WeberPenn, PruningKeepsEveryStemPointInsideEnvelope) {
  WeberPennParams p = test::weeping_willow();
  p.scale_v = 0.0f;  // scale_tree = Scale, to evaluate the envelope here
  p.levels = 3;
  p.leaves = 0;
  const TreeModel m = make_weber_penn_tree(p, 7);
  int checked = 0;
  for (size_t i = 0; i < m.stems.size(); ++i) {
    if (m.stems.level[i] == 0) continue;
    const uint32_t first = m.stems.first_section[i];
    for (uint32_t k = first + 1; k < first + m.stems.section_count[i]; ++k) {
      ++checked;
      ASSERT_TRUE(wp::inside_envelope(m.sections.positions[k], p.scale, p.base_size, p.envelope))
          << "stem " << i << " level " << int(m.stems.level[i]);
    }
  }
  EXPECT_GT(checked, 1000);
  // Unpruned, some stems reach outside.
  p.prune_ratio = 0.0f;
  const TreeModel u = make_weber_penn_tree(p, 7);
  int outside = 0;
  for (size_t i = 0; i < u.stems.size(); ++i)
    if (u.stems.level[i] > 0 &&
        !wp::inside_envelope(u.sections.positions[u.stems.first_section[i] + u.stems.section_count[i] - 1], p.scale,
                             p.base_size, p.envelope))
      ++outside;
  EXPECT_GT(outside, 0);
}

TEST(WeberPenn, ChildRadiusAtMostParentRadiusAtSpawnPoint) {
  for (const WeberPennParams& p : {test::quaking_aspen(), test::weeping_willow(), test::black_tupelo()}) {
    const TreeModel m = make_weber_penn_tree(p, 21);
    for (size_t i = 0; i < m.stems.size(); ++i) {
      const int parent = m.stems.parent[i];
      if (parent < 0) continue;
      const size_t pi = static_cast<size_t>(parent);
      const float parent_r = wp::taper_radius(p.at(m.stems.level[pi]).taper, m.stems.base_radius_m[pi],
                                              m.stems.length_m[pi], m.stems.offset_m[i] / m.stems.length_m[pi]);
      ASSERT_LE(m.stems.base_radius_m[i], parent_r * (1.0f + 1e-5f)) << i;
      ASSERT_GT(m.stems.base_radius_m[i], 0.0f);
      ASSERT_EQ(m.stems.level[i], m.stems.level[pi] + 1);
    }
  }
}

TEST(WeberPenn, LeavesOnLastStemLevelWithPositiveArea) {
  const WeberPennParams p = test::quaking_aspen();
  const TreeModel m = make_weber_penn_tree(p, 5);
  ASSERT_GT(m.leaves.size(), 1000u);
  for (size_t i = 0; i < m.leaves.size(); ++i) {
    ASSERT_EQ(m.stems.level[static_cast<size_t>(m.leaves.stem[i])], p.levels - 1);
    EXPECT_NEAR(m.leaves.length_m[i], 0.17f, 1e-6f);  // LeafScale/√quality
    EXPECT_NEAR(m.leaves.width_m[i], 0.17f, 1e-6f);   // ·LeafScaleX
  }
  const TreeMesh mesh = make_tree_mesh(m);
  ASSERT_EQ(mesh.leaves.size(), m.leaves.size());
  for (size_t i = 0; i < mesh.leaves.size(); ++i) ASSERT_NEAR(leaf_quad_area(mesh.leaves, i), 0.17f * 0.17f, 1e-5f);
}

TEST(WeberPenn, QualityScalesLeafCountAndSize) {
  WeberPennParams p = test::quaking_aspen();
  const TreeModel full = make_weber_penn_tree(p, 5);
  p.quality = 0.25f;
  const TreeModel low = make_weber_penn_tree(p, 5);
  EXPECT_EQ(count_stems_per_level(full), count_stems_per_level(low));
  EXPECT_NEAR(static_cast<double>(low.leaves.size()) / full.leaves.size(), 0.25, 0.03);
  EXPECT_NEAR(low.leaves.length_m[0], 0.17f / 0.5f, 1e-6f);
}

TEST(WeberPenn, NegativeLeavesMakeFans) {
  WeberPennParams p = test::quaking_aspen();
  p.leaves = -7;
  const TreeModel m = make_weber_penn_tree(p, 5);
  std::map<int, int> per_stem;
  for (const int s : m.leaves.stem) ++per_stem[s];
  // As many as along a stem, rounded: 7·ShapeRatio(4, offset/length_parent) = 7·(0.5 + 0.5·offset/length_parent).
  for (const auto& [stem, n] : per_stem) {
    const size_t s = static_cast<size_t>(stem);
    const float parent = m.stems.length_m[static_cast<size_t>(m.stems.parent[s])];
    EXPECT_EQ(n, static_cast<int>(std::floor(7.0f * (0.5f + 0.5f * m.stems.offset_m[s] / parent) + 0.5f))) << stem;
  }
  EXPECT_GT(per_stem.size(), 100u);
}

TEST(WeberPenn, NegativeBranchesMakeFansAtTheStemEnd) {
  WeberPennParams p = test::quaking_aspen();
  p.leaves = 0;
  p.level[2].branches = -5;
  p.level[2].rotate = 60.0f;  // the fan's angle
  const TreeModel m = make_weber_penn_tree(p, 5);
  std::map<int, int> per_parent;
  for (size_t i = 0; i < m.stems.size(); ++i) {
    if (m.stems.level[i] != 2) continue;
    const size_t parent = static_cast<size_t>(m.stems.parent[i]);
    ++per_parent[m.stems.parent[i]];
    EXPECT_FLOAT_EQ(m.stems.offset_m[i], m.stems.length_m[parent]);
    const uint32_t tip = m.stems.first_section[parent] + m.stems.section_count[parent] - 1;
    EXPECT_EQ(m.sections.positions[m.stems.first_section[i]], m.sections.positions[tip]);
  }
  EXPECT_GT(per_parent.size(), 40u);
  for (const auto& [parent, n] : per_parent) EXPECT_EQ(n, 5);
}

TEST(WeberPenn, SameSeedBitIdenticalDifferentSeedSimilarCounts) {
  for (const WeberPennParams& p : {test::quaking_aspen(), test::weeping_willow()}) {
    const TreeMesh a = make_tree_mesh(make_weber_penn_tree(p, 42));
    const TreeMesh b = make_tree_mesh(make_weber_penn_tree(p, 42));
    ASSERT_EQ(a.stems.positions.size(), b.stems.positions.size());
    ASSERT_EQ(a.leaves.corners.size(), b.leaves.corners.size());
    EXPECT_EQ(std::memcmp(a.stems.positions.data(), b.stems.positions.data(), a.stems.positions.size() * sizeof(Vec3)),
              0);
    EXPECT_EQ(
        std::memcmp(a.stems.triangles.data(), b.stems.triangles.data(), a.stems.triangles.size() * sizeof(glm::uvec3)),
        0);
    EXPECT_EQ(std::memcmp(a.leaves.corners.data(), b.leaves.corners.data(), a.leaves.corners.size() * sizeof(Vec3)), 0);

    const TreeModel m1 = make_weber_penn_tree(p, 42), m2 = make_weber_penn_tree(p, 43);
    EXPECT_NE(m1.sections.positions.back(), m2.sections.positions.back());
    const std::vector<int> n1 = count_stems_per_level(m1), n2 = count_stems_per_level(m2);
    ASSERT_EQ(n1.size(), n2.size());
    for (size_t l = 0; l < n1.size(); ++l) EXPECT_NEAR(n1[l], n2[l], 0.35 * std::max(n1[l], n2[l]) + 2) << l;
  }
}

TEST(WeberPenn, WindMovesStemsWithoutChangingStructure) {
  for (WeberPennParams p : {test::quaking_aspen(), test::weeping_willow()}) {
    const TreeModel calm = make_weber_penn_tree(p, 8);
    p.wind.speed = 5.0f;
    p.wind.gust = 2.0f;
    p.wind.time_s = 1.0f;
    const TreeModel t1 = make_weber_penn_tree(p, 8);
    p.wind.time_s = 2.0f;
    const TreeModel t2 = make_weber_penn_tree(p, 8);
    EXPECT_EQ(count_stems_per_level(calm), count_stems_per_level(t1));
    EXPECT_EQ(count_stems_per_level(t1), count_stems_per_level(t2));
    EXPECT_EQ(calm.leaves.size(), t1.leaves.size());
    EXPECT_EQ(calm.stems.length_m, t1.stems.length_m);
    EXPECT_NE(calm.sections.positions.back(), t1.sections.positions.back());
    EXPECT_NE(t1.sections.positions.back(), t2.sections.positions.back());
    EXPECT_EQ(calm.sections.positions[0], t1.sections.positions[0]);  // the base does not move
  }
}

TEST(WeberPenn, LevelsDeeperThanThreeReuseLevelThree) {
  WeberPennParams p = test::quaking_aspen();
  p.levels = 5;
  p.level[1].branches = 6;
  p.level[2].branches = 4;
  p.level[3].length = 0.5f;
  p.level[3].branches = 3;
  p.level[3].curve_res = 2;
  const TreeModel m = make_weber_penn_tree(p, 6);
  const std::vector<int> n = count_stems_per_level(m);
  ASSERT_EQ(n.size(), 5u);
  EXPECT_GT(n[4], n[3]);
  for (size_t i = 0; i < m.stems.size(); ++i)
    if (m.stems.level[i] == 4) {
      EXPECT_EQ(m.stems.section_count[i], 3u);  // 3CurveRes = 2 segments
      const size_t parent = static_cast<size_t>(m.stems.parent[i]);
      EXPECT_NEAR(m.stems.length_m[i], 0.5f * (m.stems.length_m[parent] - 0.6f * m.stems.offset_m[i]), 1e-5f);
    }
  for (const int stem : m.leaves.stem) ASSERT_EQ(m.stems.level[static_cast<size_t>(stem)], 4);
}

TEST(WeberPenn, ZScaleScalesVertically) {
  WeberPennParams p = bare_trunk();
  p.z_scale = 0.5f;
  const TreeModel m = make_weber_penn_tree(p, 1);
  EXPECT_NEAR(m.sections.positions.back().z, 5.0f, 1e-4f);
}

TEST(WeberPenn, FourAppendixSpeciesAreSensible) {
  for (const WeberPennParams& p :
       {test::quaking_aspen(), test::black_tupelo(), test::weeping_willow(), test::california_black_oak()}) {
    const TreeModel m = make_weber_penn_tree(p, 1);
    const std::vector<int> n = count_stems_per_level(m);
    EXPECT_EQ(static_cast<int>(n.size()), p.levels);
    EXPECT_GT(m.leaves.size(), 1000u);
    for (const Vec3& q : m.sections.positions) ASSERT_TRUE(is_finite(q));
    for (const float r : m.sections.radius_m) ASSERT_GE(r, 0.0f);
  }
}

TEST(WeberPenn, SegmentsBelowASplitKeepTheirFullChildCount) {
  // A trunk of 4 segments that splits in two at the end of segment 0: segment 0 carries its full
  // share (nBranches/4), each segment above the split half of it on each of the two stems, so the
  // tree has nBranches children in all (Arbaro spawns per segment before it splits).
  for (const wp::Reading reading : {wp::Reading::Paper, wp::Reading::Arbaro}) {
    WeberPennParams p = bare_trunk();
    p.reading = reading;
    p.levels = 2;
    p.base_size = 0.0f;
    p.shape = 3;
    p.base_splits = 1;
    p.level[0].curve_res = 4;
    p.level[0].split_angle = 20.0f;
    p.level[1].branches = 80;
    p.level[1].curve_res = 1;
    const TreeModel m = make_weber_penn_tree(p, 4);
    int below = 0, total = 0;
    for (size_t i = 0; i < m.stems.size(); ++i) {
      if (m.stems.level[i] != 1) continue;
      ++total;
      if (m.stems.parent[i] == 0 && m.stems.offset_m[i] < 2.5f) ++below;
    }
    EXPECT_NEAR(below, 20, 1);
    EXPECT_NEAR(total, 80, 2);
  }
}

TEST(WeberPenn, LeavesOfClonesByReading) {
  // One level-1 stem that splits once: the paper reading shares the leaves of the segments above
  // the split between the two stems, Arbaro's gives each stem the full count.
  std::map<wp::Reading, size_t> leaves;
  for (const wp::Reading reading : {wp::Reading::Paper, wp::Reading::Arbaro}) {
    WeberPennParams p = attraction_tree(0.0f);
    p.reading = reading;
    p.levels = 2;
    p.leaves = 40;
    p.leaf_distrib = 3;  // the same count on every stem
    p.level[1].curve_res = 4;
    p.level[1].seg_splits = 1.0f;
    p.level[1].split_angle = 20.0f;
    const TreeModel m = make_weber_penn_tree(p, 2);
    leaves[reading] = m.leaves.size();
  }
  // Paper: 10 below the first split, then halved at every split of every stem: fewer than Arbaro's.
  EXPECT_LT(leaves[wp::Reading::Paper], leaves[wp::Reading::Arbaro]);
}

TEST(WeberPenn, ZeroBranchesMakesSeveralTrunks) {
  WeberPennParams p = bare_trunk();
  p.level[0].curve_res = 3;
  p.level[0].branches = 5;
  p.level[0].down_angle = 20.0f;
  p.level[0].rotate = 72.0f;
  p.level[0].branch_dist = 0.3f;
  const TreeModel m = make_weber_penn_tree(p, 6);
  ASSERT_EQ(m.stems.size(), 5u);
  std::vector<float> azimuth;
  for (size_t i = 0; i < m.stems.size(); ++i) {
    EXPECT_EQ(m.stems.level[i], 0);
    EXPECT_FALSE(m.stems.is_clone(i));
    // Leaning 20°, a trunk stands higher by its base radius times sin 20° (its ring stays above the ground).
    const Vec3 base = m.sections.positions[m.stems.first_section[i]];
    const float lift = m.sections.radius_m[m.stems.first_section[i]] * (1.0f + p.lobe_depth) * std::sin(radians(20.0f));
    EXPECT_NEAR(base.z, lift, 1e-4f);
    EXPECT_LE(glm::length(Vec2(base)), 0.3f + 1e-6f);
    const Vec3 d = first_direction(m, i);
    EXPECT_NEAR(angle_deg(d, Vec3(0, 0, 1)), 20.0f, 1e-3f);
    azimuth.push_back(degrees(std::atan2(d.y, d.x)));
  }
  for (size_t i = 1; i < azimuth.size(); ++i)
    EXPECT_NEAR(std::abs(std::remainder(azimuth[i] - azimuth[i - 1], 360.0f)), 72.0f, 1e-2f);
  // One trunk (the default) is the tree it always was: the other trunks draw their own streams.
  WeberPennParams one = p;
  one.level[0].branches = 1;
  one.level[0].down_angle = 0.0f;
  EXPECT_EQ(make_weber_penn_tree(one, 6).stems.size(), 1u);
}

TEST(WeberPenn, NothingBelowTheGroundOnFlatGround) {
  // Every mesh vertex and leaf corner of the four appendix species, over many seeds and both
  // readings, lies at z ≥ 0 (before this rule the oak's low limbs dipped 2 m below the ground).
  for (const WeberPennParams& species :
       {test::quaking_aspen(), test::black_tupelo(), test::weeping_willow(), test::california_black_oak()}) {
    for (const wp::Reading reading : {wp::Reading::Paper, wp::Reading::Arbaro}) {
      WeberPennParams p = species;
      p.reading = reading;
      p.quality = 0.25f;  // fewer leaves: the rule does not depend on their number
      for (uint64_t seed = 1; seed <= 8; ++seed) {
        const TreeMesh mesh = make_tree_mesh(make_weber_penn_tree(p, seed), {});
        float lowest = 0.0f;
        for (const Vec3& q : mesh.stems.positions) lowest = std::min(lowest, q.z);
        for (const Vec3& q : mesh.leaves.corners) lowest = std::min(lowest, q.z);
        EXPECT_GE(lowest, -1e-4f) << "levels " << p.levels << " seed " << seed;
      }
    }
  }
  // A trunk that may start below the horizontal asks for it: then nothing is held up.
  WeberPennParams down = bare_trunk();
  down.level[0].down_angle = 120.0f;
  ASSERT_TRUE(down.asks_below_ground());
  const TreeModel m = make_weber_penn_tree(down, 1);
  EXPECT_LT(m.sections.positions.back().z, -1.0f);
  EXPECT_FALSE(test::california_black_oak().asks_below_ground());
}

}  // namespace
}  // namespace sylva
