// Hart & Baker growth (geometry/trees/hart_baker/hart_baker.h): the closed forms of §3.4 and §4.1
// against numerical integration, the recursive sums (eq. 10, 12, 14, 15) on hand-built
// hierarchies, mass conservation of the growth step (eq. 16–22), pruning, leaves and determinism.

#include "core/error.h"
#include "geometry/trees/hart_baker/hart_baker.h"
#include "geometry/trees/tree_mesher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace sylva {
namespace {

constexpr double kPiD = 3.14159265358979323846;

// ∫ π ρ(s)² ds and ∫ s π ρ(s)² ds by the midpoint rule, ρ linear from R to r.
std::pair<double, double> integrate_frustum(double l, double R, double r) {
  const int n = 200000;
  double v = 0.0, vs = 0.0;
  for (int k = 0; k < n; ++k) {
    const double s = (k + 0.5) / n * l;
    const double rho = R + (r - R) * s / l;
    const double dv = kPiD * rho * rho * l / n;
    v += dv;
    vs += s * dv;
  }
  return {v, vs / v};
}

TEST(HartBaker, FrustumVolumeAndCentroidMatchIntegration) {
  const double cases[][3] = {{2.0, 0.3, 0.1}, {1.0, 0.5, 0.0}, {3.0, 0.2, 0.2}, {0.7, 0.1, 0.3}};
  for (const auto& c : cases) {
    const auto [v, h] = integrate_frustum(c[0], c[1], c[2]);
    EXPECT_NEAR(frustum_volume(c[0], c[1], c[2]), v, 1e-6 * v) << c[0] << " " << c[1] << " " << c[2];
    EXPECT_NEAR(frustum_centroid(c[0], c[1], c[2]), h, 1e-6 * c[0]);
  }
  // Eq. 11's special cases: a cone's centre of mass at l/4, a cylinder's at l/2; eq. 9's paper form.
  EXPECT_DOUBLE_EQ(frustum_centroid(4.0, 1.0, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(frustum_centroid(4.0, 1.0, 1.0), 2.0);
  const double l = 2.0, R = 0.3, r = 0.1;
  EXPECT_NEAR(frustum_volume(l, R, r), kPiD * l * (R * R * R - r * r * r) / (3.0 * (R - r)), 1e-12);
  const double paper = l * (std::pow(R, 4) - r * r * r * (4 * R - 3 * r)) / (4 * (R - r) * (R * R * R - r * r * r));
  EXPECT_NEAR(frustum_centroid(l, R, r), paper, 1e-12);
}

TEST(HartBaker, SupportsAndNeedsToSupportAreInverse) {
  const double H = 91.44;  // 300 feet: k = π·100 feet (eq. 8)
  EXPECT_NEAR(supports(1.0, 1.0, H), kPiD * 30.48, 1e-9);
  for (const double R : {0.001, 0.05, 0.4, 2.0})
    for (const double d : {350.0, 800.0}) {
      EXPECT_NEAR(needs_to_support(supports(R, d, H), d, H), R, 1e-12 * std::max(1.0, R));
      const double m = 37.0 * R;
      EXPECT_NEAR(supports(needs_to_support(m, d, H), d, H), m, 1e-9 * m);
    }
  // A cone of height H supports exactly its own weight (eq. 8).
  EXPECT_NEAR(supports(0.3, 600.0, H), 600.0 * frustum_volume(H, 0.3, 0.0), 1e-6);
  // Eq. 21 inverts eq. 9.
  const double m = 600.0 * frustum_volume(1.7, 0.05, 0.01);
  EXPECT_NEAR(length_for_mass(m, 0.05, 0.2, 600.0), 1.7, 1e-9);
}

// Trunk up the Z axis, one limb out +X from its top, one out −Y from half-way, a grandchild.
HartBakerTree hand_built(const HartBakerParams& p) {
  HartBakerTree t = make_hart_baker_seedling(p, 5);
  t.length_m[0] = 2.0f;
  t.radius_m[0] = 0.1f;
  auto add = [&](int32_t parent, Vec3 base, Vec3 dir, float l, float R) {
    t.parent.push_back(parent);
    t.order.push_back(static_cast<uint8_t>(t.order[static_cast<size_t>(parent)] + 1));
    t.alive.push_back(1);
    t.born.push_back(0);
    t.base.push_back(base);
    t.direction.push_back(dir);
    t.length_m.push_back(l);
    t.radius_m.push_back(R);
    t.apex.push_back(-1);
    t.lit.push_back(1.0f);
    t.ring_radius_m.emplace_back();
    t.ring_length_m.emplace_back();
    t.ring_offset_m.emplace_back();
    t.reaction_m.emplace_back(0.0f);
  };
  add(0, {0, 0, 2}, {1, 0, 0}, 1.0f, 0.03f);
  add(0, {0, 0, 1}, {0, -1, 0}, 0.5f, 0.02f);
  add(1, {0.5f, 0, 2}, {0, 0, 1}, 0.4f, 0.01f);
  return t;
}

TEST(HartBaker, RecursiveSumsOnAHandBuiltHierarchy) {
  HartBakerParams p;
  p.phototropism = true;
  const HartBakerTree t = hand_built(p);
  const std::vector<float> light = {0.0f, 0.2f, 0.05f, 0.1f};
  const LimbSums s = compute_limb_sums(t, p, light);
  const double d = p.wood_density_kg_m3;
  double total = 0.0;
  DVec3 moment(0.0);
  for (size_t i = 0; i < 4; ++i) {
    const double R = t.radius_m[i], r = p.tip_ratio * R, l = t.length_m[i];
    EXPECT_NEAR(s.m[i], d * frustum_volume(l, R, r), 1e-9);
    const DVec3 x = DVec3(t.base[i]) + DVec3(t.direction[i]) * frustum_centroid(l, R, r);
    EXPECT_NEAR(glm::length(s.x[i] - x), 0.0, 1e-6);
    total += s.m[i];
    moment += x * s.m[i];
  }
  EXPECT_NEAR(s.M[0], total, 1e-9 * total);  // eq. 10
  EXPECT_NEAR(s.M[1], s.m[1] + s.m[3], 1e-12);
  EXPECT_NEAR(glm::length(s.X[0] - moment / total), 0.0, 1e-6);  // eq. 12
  EXPECT_NEAR(glm::length(s.X[1] - (s.x[1] * s.m[1] + s.x[3] * s.m[3]) / s.M[1]), 0.0, 1e-6);
  EXPECT_NEAR(s.P[0], 0.35, 1e-6);  // eq. 14
  EXPECT_NEAR(s.P[1], 0.3, 1e-6);
  EXPECT_NEAR(s.G[0], s.g[0] + s.g[1] + s.g[2] + s.g[3], 1e-12);  // eq. 15
  EXPECT_NEAR(s.G[1], s.g[1] + s.g[3], 1e-12);
  // Eq. 13 (our sign: growth opposes the offset of the centre of mass, in trunk radii, clamped):
  // the crown's weight sits towards +X, so the limb growing +X is told to slow down.
  EXPECT_GT(s.X[0].x, 0.0);
  EXPECT_LT(s.o[1], 0.0);
  for (size_t i = 0; i < 4; ++i) {
    const double o = -glm::dot(DVec3(t.direction[i]), DVec3(s.X[0].x, s.X[0].y, 0.0)) / t.radius_m[0];
    EXPECT_NEAR(s.o[i], std::clamp(o, -1.0, 1.0), 1e-9);
  }
  EXPECT_GE(s.o[1], -1.0);
}

TEST(HartBaker, LightArrayMustMatchTheLimbs) {
  HartBakerParams p;
  const HartBakerTree t = hand_built(p);
  EXPECT_THROW(compute_limb_sums(t, p, {1.0f}), Error);
}

TEST(HartBaker, GrowthStepConservesTheAllottedMass) {
  for (const bool light : {false, true}) {
    HartBakerParams p;
    p.phototropism = light;
    HartBakerTree t = hand_built(p);
    const std::vector<float> lit = {0.0f, 0.01f, 0.005f, 0.02f};
    const double before = compute_limb_sums(t, p, lit).M[0];
    const size_t limbs = t.size();
    const GrowthReport r = grow_hart_baker_year(t, p, lit);
    ASSERT_GT(r.mass_allotted_kg, 0.0);
    EXPECT_NEAR(r.mass_added_kg, r.mass_allotted_kg, 1e-4 * r.mass_allotted_kg);
    // Measured independently from the state (the new buds excluded).
    double after = 0.0;
    for (size_t i = 0; i < limbs; ++i)
      after += p.wood_density_kg_m3 * frustum_volume(t.length_m[i], t.radius_m[i], p.tip_ratio * t.radius_m[i]);
    EXPECT_NEAR(after - before, r.mass_allotted_kg, 1e-4 * r.mass_allotted_kg);
    EXPECT_EQ(t.year, 1);
  }
}

TEST(HartBaker, GrowsDeterministicallyFromTheSeed) {
  HartBakerParams p;
  p.years = 8;
  const TreeModel a = make_tree(p, 3, {});
  const TreeModel b = make_tree(p, 3, {});
  const TreeModel c = make_tree(p, 4, {});
  ASSERT_EQ(a.stems.size(), b.stems.size());
  EXPECT_EQ(a.sections.positions, b.sections.positions);
  EXPECT_EQ(a.sections.radius_m, b.sections.radius_m);
  EXPECT_NE(a.sections.positions, c.sections.positions);
  EXPECT_GT(a.stems.size(), 5u);
  EXPECT_GT(a.leaves.size(), 10u);
  // The tree grows: taller and with a thicker trunk every year, one ring a year.
  HartBakerTree t = make_hart_baker_seedling(p, 3);
  auto height = [](const HartBakerTree& tree) {
    float top = 0.0f;
    for (size_t i = 0; i < tree.size(); ++i)
      if (tree.alive[i]) top = std::max(top, (tree.base[i] + tree.direction[i] * tree.length_m[i]).z);
    return top;
  };
  float top = height(t), radius = t.radius_m[0];
  for (int y = 0; y < 6; ++y) {
    grow_hart_baker_year(t, p, {});
    EXPECT_GT(height(t), top);
    EXPECT_GT(t.radius_m[0], radius);
    top = height(t);
    radius = t.radius_m[0];
    EXPECT_EQ(t.ring_radius_m[0].size(), static_cast<size_t>(y + 1));
  }
}

TEST(HartBaker, PruningRemovesTheSubtree) {
  HartBakerParams p;
  HartBakerTree t = hand_built(p);
  prune_hart_baker_limb(t, 1);
  EXPECT_EQ(t.alive[1], 0);
  EXPECT_EQ(t.alive[3], 0);  // carried by limb 1
  EXPECT_EQ(t.alive[2], 1);
  EXPECT_THROW(prune_hart_baker_limb(t, 0), Error);
  EXPECT_THROW(prune_hart_baker_limb(t, 1), Error);
  EXPECT_THROW(prune_hart_baker_limb(t, 99), Error);
  const LimbSums s = compute_limb_sums(t, p, std::vector<float>(t.size(), 0.0f));
  EXPECT_NEAR(s.M[0], s.m[0] + s.m[2], 1e-12);
  EXPECT_EQ(hart_baker_tree_model(t, p).stems.size(), 2u);
}

TEST(HartBaker, PruningMakesTheRestCompensate) {
  // §6.1: cutting the heavy +X limb moves the centre of mass to the −Y limb's side, so eq. 13 now
  // speeds up a shoot growing +Y (away from it) and slows one growing −Y.
  HartBakerParams p;
  HartBakerTree t = hand_built(p);
  t.direction[3] = Vec3(0, 1, 0);
  const LimbSums before = compute_limb_sums(t, p, {});
  EXPECT_GT(before.X[0].x, 0.0);
  prune_hart_baker_limb(t, 1);
  // A new shoot growing +Y from the trunk's top, standing in for the rest of the crown.
  t.parent.push_back(0);
  t.order.push_back(1);
  t.alive.push_back(1);
  t.born.push_back(0);
  t.base.push_back({0, 0, 2});
  t.direction.push_back({0, 1, 0});
  t.length_m.push_back(0.1f);
  t.radius_m.push_back(0.004f);
  t.apex.push_back(-1);
  t.lit.push_back(1.0f);
  t.ring_radius_m.emplace_back();
  t.ring_length_m.emplace_back();
  t.ring_offset_m.emplace_back();
  t.reaction_m.emplace_back(0.0f);
  const LimbSums after = compute_limb_sums(t, p, {});
  EXPECT_LT(after.X[0].y, 0.0);
  EXPECT_GT(after.o[4], 0.0);
  EXPECT_LT(after.o[2], 0.0);
}

TEST(HartBaker, LeavesGrowOnThinLimbsAndFaceUp) {
  HartBakerParams p;
  p.leaf_radius_m = 0.021f;
  const HartBakerTree t = hand_built(p);
  const TreeLeaves leaves = hart_baker_leaves(t, p);
  ASSERT_GT(leaves.size(), 0u);
  std::vector<int> per_limb(t.size(), 0);
  for (size_t k = 0; k < leaves.size(); ++k) {
    const size_t limb = static_cast<size_t>(leaves.stem[k]);
    ++per_limb[limb];
    const float s = glm::dot(leaves.positions[k] - t.base[limb], t.direction[limb]);
    const float R = t.radius_m[limb];
    EXPECT_LT(R + (p.tip_ratio * R - R) * s / t.length_m[limb], p.leaf_radius_m);
    EXPECT_GE(leaves.frames[k].y.z, 0.0f);
    EXPECT_NEAR(glm::dot(leaves.frames[k].z, t.direction[limb]), 0.0f, 1e-5f);
  }
  EXPECT_EQ(per_limb[0], 0);  // the trunk tapers from 0.1 m to 0.02 m: too thick at every leaf slot
  EXPECT_GT(per_limb[1], 0);  // 0.03 m → 0.006 m: leaves on its outer part only
  EXPECT_LT(per_limb[1], static_cast<int>(1.0f / p.leaf_spacing_m));
  EXPECT_GT(per_limb[2], 0);
}

TEST(HartBaker, ReactionWoodSidesDependOnTheWoodClass) {
  // A limb leaning out +X carries its weight off-centre: compression wood (gymnosperm) forms on
  // the side towards the load, below; tension wood (angiosperm) above.
  for (const WoodClass wood : {WoodClass::Gymnosperm, WoodClass::Angiosperm}) {
    HartBakerParams p;
    p.wood = wood;
    p.phototropism = false;
    HartBakerTree t = hand_built(p);
    t.direction[1] = glm::normalize(Vec3(1, 0, 1));
    t.radius_m[1] = 0.005f;  // past the slenderness limit: the shoot thickens as it grows
    t.radius_m[3] = 0.004f;
    grow_hart_baker_year(t, p, {});
    const Vec3 offset = t.reaction_m[1];
    ASSERT_GT(glm::length(offset), 0.0f);
    if (wood == WoodClass::Gymnosperm)
      EXPECT_LT(offset.z, 0.0f);
    else
      EXPECT_GT(offset.z, 0.0f);
  }
}

// The stem of limb `limb` in hart_baker_tree_model's output (stems follow the living limbs in order).
size_t stem_of(const HartBakerTree& t, size_t limb) {
  size_t stem = 0;
  for (size_t i = 0; i < limb; ++i) stem += t.alive[i];
  return stem;
}

TEST(HartBaker, YearlySegmentsJoinWithoutAStep) {
  // Along every axis the drawn tip of one year's segment is the drawn base of the next: the same
  // centre and radius, so the tube has no step where yearly segments meet (and a thin continuation
  // on a thick tip tapers into it instead of stepping down).
  for (const WoodClass wood : {WoodClass::Angiosperm, WoodClass::Gymnosperm}) {
    HartBakerParams p;
    p.wood = wood;
    p.years = 9;
    HartBakerTree t = make_hart_baker_seedling(p, 3);
    for (int y = 0; y < p.years; ++y) grow_hart_baker_year(t, p, {});
    const TreeModel model = hart_baker_tree_model(t, p);
    int joins = 0, stepped_before = 0, turned = 0;
    float worst = 0.0f, worst_plane = 0.0f;
    for (size_t i = 0; i < t.size(); ++i) {
      const int32_t apex = t.apex[i];
      if (!t.alive[i] || apex < 0 || !t.alive[static_cast<size_t>(apex)]) continue;
      const uint32_t tip = model.stems.first_section[stem_of(t, i)] + model.stems.section_count[stem_of(t, i)] - 1;
      const uint32_t base = model.stems.first_section[stem_of(t, static_cast<size_t>(apex))];
      const float R = model.sections.radius_m[tip];
      // Both end rings lie in one plane: the mesher sets the last ring by the last piece and the
      // first by the first frame; both are the bisector of the two axes.
      const Vec3 last_piece = glm::normalize(model.sections.positions[tip] - model.sections.positions[tip - 1]);
      const Vec3 bisector = glm::normalize(t.direction[i] + t.direction[static_cast<size_t>(apex)]);
      worst_plane = std::max(worst_plane, glm::length(last_piece - bisector));
      worst_plane = std::max(worst_plane, glm::length(model.sections.frames[base].z - bisector));
      turned += glm::dot(t.direction[i], t.direction[static_cast<size_t>(apex)]) < 0.9999f;
      worst = std::max(worst, std::abs(model.sections.radius_m[base] - R) / R);
      worst = std::max(worst, glm::length(model.sections.positions[base] - model.sections.positions[tip]) / R);
      // What a plain cone-per-segment drawing would show there: r_i against R_apex.
      stepped_before += std::abs(t.tip_radius(i, p) - t.radius_m[static_cast<size_t>(apex)]) > 0.05f * R;
      ++joins;
    }
    ASSERT_GT(joins, 100);
    EXPECT_LT(worst, 1e-5f);
    EXPECT_LT(worst_plane, 1e-3f);
    EXPECT_GT(turned, joins / 2);  // the axes do turn at most joins
    EXPECT_GT(stepped_before, 0);  // the joins this test guards would otherwise step
  }
}

TEST(HartBaker, ReactionWoodBulgesOnItsSide) {
  // Eq. 31 on the drawn surface: a lateral's base section is its outer ring, moved toward ŷ by the
  // ring centre's offset, so the base stands out on that side — below (compression wood) for a
  // gymnosperm, above (tension wood) for an angiosperm — and falls back on the other.
  for (const WoodClass wood : {WoodClass::Gymnosperm, WoodClass::Angiosperm}) {
    HartBakerParams p;
    p.wood = wood;
    p.reaction_wood = 1.0f;
    HartBakerTree t = make_hart_baker_seedling(p, 5);
    for (int y = 0; y < 14; ++y) grow_hart_baker_year(t, p, {});
    const TreeModel model = hart_baker_tree_model(t, p);
    int laterals = 0, right_side = 0;
    for (size_t i = 1; i < t.size(); ++i) {
      const size_t parent = static_cast<size_t>(t.parent[i]);
      // Laterals leaning at least 45° from upright: the weight bends them down.
      const bool lateral = t.alive[i] && t.order[i] > t.order[parent] && t.direction[i].z < 0.7f;
      if (!lateral || glm::length(t.reaction_m[i]) < 1e-3f * t.radius_m[i]) continue;
      const uint32_t base = model.stems.first_section[stem_of(t, i)];
      const Vec3 shift = model.sections.positions[base] - t.base[i];
      const float r = model.sections.radius_m[base];
      // The section's extent on the side of the shift and against it.
      EXPECT_NEAR(r, t.radius_m[i], 1e-6f);
      EXPECT_NEAR(glm::length(shift), glm::length(t.reaction_m[i]), 1e-6f);
      ++laterals;
      right_side += wood == WoodClass::Gymnosperm ? shift.z < 0.0f : shift.z > 0.0f;
    }
    ASSERT_GT(laterals, 20);
    EXPECT_EQ(right_side, laterals);
  }
}

TEST(HartBaker, ReactionWoodReachIsEq25) {
  // δ_i = W_i X̄_i sin θ_X / (F_R sin θ_d) (eq. 24–25) by hand on the hand-built tree: W = M g,
  // X̄ sin θ_X the horizontal lever of the supported centre of mass from the limb's base, F_R =
  // supports(R) g (eq. 6), θ_d the angle to the parent.
  HartBakerParams p;
  HartBakerTree t = hand_built(p);
  t.radius_m[1] = 0.01f;
  const LimbSums s = compute_limb_sums(t, p, {});
  const std::vector<double> reach = reaction_wood_reach(t, p, s);
  const double d = p.wood_density_kg_m3, k_d = kPi * p.max_height_m / 3.0 * d;
  const double tau = p.tip_ratio;
  // Limb 1 leaves the trunk's top along +X (θ_d = 90°) and carries limb 3 upright at x = 0.5.
  const double m1 = d * frustum_volume(1.0, 0.01, 0.01 * tau), x1 = frustum_centroid(1.0, 0.01, 0.01 * tau);
  const double m3 = d * frustum_volume(0.4, 0.01, 0.01 * tau);
  EXPECT_NEAR(reach[1], (m1 * x1 + m3 * 0.5) / (k_d * 0.01 * 0.01), 1e-6 * reach[1]);
  // Limb 2 leaves half-way up along −Y and carries nothing.
  const double m2 = d * frustum_volume(0.5, 0.02, 0.02 * tau), x2 = frustum_centroid(0.5, 0.02, 0.02 * tau);
  EXPECT_NEAR(reach[2], m2 * x2 / (k_d * 0.02 * 0.02), 1e-6 * reach[2]);
  EXPECT_EQ(reach[3], 0.0);  // upright, its weight straight above its base: no lever
  // The trunk: the whole tree's horizontal offset, θ_d = 90°.
  EXPECT_NEAR(reach[0], s.M[0] * std::hypot(s.X[0].x, s.X[0].y) / (k_d * 0.1 * 0.1), 1e-6 * reach[0]);
  // A limb leaning along its parent has sin θ_d → 0: nothing to resist, no reach.
  t.direction[2] = Vec3(0, 0, 1);
  EXPECT_EQ(reaction_wood_reach(t, p, compute_limb_sums(t, p, {}))[2], 0.0);
}

TEST(HartBaker, ReactionWoodBulgeFallsOffOverDelta) {
  // Eq. 31's c(t l/δ): the drawn centre of a limb's sections leaves the axis by the ring offset
  // times c(s/δ), full at the base, gone at δ, with sections over [0, δ] then the tip.
  EXPECT_EQ(reaction_wood_falloff(0.0), 1.0);
  EXPECT_EQ(reaction_wood_falloff(1.0), 0.0);
  EXPECT_EQ(reaction_wood_falloff(2.0), 0.0);
  EXPECT_NEAR(reaction_wood_falloff(0.5), 0.5, 1e-12);
  for (double u = 0.0; u < 1.0; u += 0.05) EXPECT_GT(reaction_wood_falloff(u), reaction_wood_falloff(u + 0.05));
  HartBakerParams p;
  HartBakerTree t = hand_built(p);
  t.radius_m[1] = 0.01f;
  const Vec3 offset(0.0f, 0.0f, 0.004f);
  t.reaction_m[1] = offset;
  const double delta = reaction_wood_reach(t, p, compute_limb_sums(t, p, {}))[1];
  ASSERT_GT(delta, t.radius_m[1]);
  ASSERT_LT(delta, 0.5 * t.length_m[1]);
  const TreeModel model = hart_baker_tree_model(t, p);
  const size_t stem = stem_of(t, 1);
  const uint32_t first = model.stems.first_section[stem];
  ASSERT_EQ(model.stems.section_count[stem], static_cast<uint32_t>(kReactionSections + 2));
  for (uint32_t k = 0; k < model.stems.section_count[stem]; ++k) {
    const float arc = model.sections.arc_m[first + k];
    const Vec3 axis = t.base[1] + t.direction[1] * arc;
    const Vec3 shift = model.sections.positions[first + k] - axis;
    EXPECT_NEAR(glm::length(shift - offset * static_cast<float>(reaction_wood_falloff(arc / delta))), 0.0f, 1e-6f)
        << "section " << k << " at " << arc;
    if (k > 0 && k <= static_cast<uint32_t>(kReactionSections)) {
      EXPECT_NEAR(arc, delta * k / kReactionSections, 1e-6);
    }
  }
  EXPECT_FLOAT_EQ(model.sections.arc_m[first + kReactionSections + 1], t.length_m[1]);
  // Without reaction wood a limb is one cone: base and tip.
  EXPECT_EQ(model.stems.section_count[stem_of(t, 2)], 2u);
}

TEST(HartBaker, MeshesThroughTheSharedMesher) {
  HartBakerParams p;
  p.years = 5;
  const TreeModel model = make_tree(p, 1, {});
  const TreeMesh mesh = make_tree_mesh(model);
  EXPECT_GT(mesh.stems.triangles.size(), 20u);
  EXPECT_EQ(mesh.leaves.size(), model.leaves.size());
}

}  // namespace
}  // namespace sylva
