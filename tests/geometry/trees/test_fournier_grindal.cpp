// Fournier–Grindal normal splitting (geometry/trees/fournier_grindal/, seed 001 §2.1): angle and
// split-point statistics against μ/σ, the ratio per generation, the outward-octant pruning rule,
// determinism, and the tree's two solids (crown, hexagonal trunk §5).

#include "core/error.h"
#include "geometry/trees/fournier_grindal/fournier_grindal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sylva {
namespace {

FournierGrindalParams octahedron() {
  FournierGrindalParams p;
  p.normals = {{3, 0, 0}, {-3, 0, 0}, {0, 3, 0}, {0, -3, 0}, {0, 0, 4}, {0, 0, -2}};
  p.generations = 3;
  p.mu_alpha_deg = 30.0f;
  p.sigma_alpha_deg = 8.0f;
  p.mu_b = 0.3f;
  p.sigma_b = 0.05f;
  p.ratio = 0.5f;
  return p;
}

struct Moments {
  double mean = 0, sd = 0;
  size_t n = 0;
};
Moments moments(const std::vector<double>& v) {
  Moments m;
  m.n = v.size();
  for (double x : v) m.mean += x;
  m.mean /= static_cast<double>(v.size());
  for (double x : v) m.sd += (x - m.mean) * (x - m.mean);
  m.sd = std::sqrt(m.sd / static_cast<double>(v.size() - 1));
  return m;
}

TEST(FournierGrindal, SplitAnglesMatchMuSigmaAndShrinkByRatio) {
  const FournierGrindalParams p = octahedron();
  std::vector<std::vector<double>> angles(4), bc(4);
  for (uint64_t seed = 1; seed <= 300; ++seed) {
    const FgCrown c = make_fournier_grindal_crown(p, seed);
    for (const FgNormal& n : c.history) {
      if (n.parent < 0) continue;
      const FgNormal& parent = c.history[size_t(n.parent)];
      angles[size_t(n.generation)].push_back(
          std::acos(std::clamp(glm::dot(n.direction, parent.direction), -1.0f, 1.0f)) * 180.0 / std::numbers::pi);
      const Vec3 tip = parent.origin + parent.length * parent.direction;
      bc[size_t(n.generation)].push_back(glm::length(tip - n.origin) / parent.length);
    }
  }
  double mu = p.mu_alpha_deg, sigma = p.sigma_alpha_deg;
  for (int g = 1; g <= 3; ++g) {
    const Moments a = moments(angles[size_t(g)]);
    ASSERT_GT(a.n, 1000u);
    EXPECT_NEAR(a.mean, mu, 4.0 * sigma / std::sqrt(double(a.n)) + 0.05) << "generation " << g;
    EXPECT_NEAR(a.sd, sigma, 0.1 * sigma) << "generation " << g;
    const Moments b = moments(bc[size_t(g)]);
    // Two children per split share B: the distances come in equal pairs.
    EXPECT_NEAR(b.mean, p.mu_b, 4.0 * p.sigma_b / std::sqrt(double(b.n) / 2.0)) << "generation " << g;
    EXPECT_NEAR(b.sd, p.sigma_b, 0.15 * p.sigma_b) << "generation " << g;
    mu *= p.ratio;
    sigma *= p.ratio;
  }
}

TEST(FournierGrindal, PruningKeepsOnlyOutwardNormals) {
  const FournierGrindalParams p = octahedron();
  size_t rejected = 0, kept = 0;
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    const FgCrown c = make_fournier_grindal_crown(p, seed);
    for (const FgNormal& n : c.history) {
      if (n.parent < 0) continue;
      const bool outward =
          n.direction.x * n.origin.x >= 0 && n.direction.y * n.origin.y >= 0 && n.direction.z * n.origin.z >= 0;
      EXPECT_EQ(n.kept, outward && n.length > 0);
      (n.kept ? kept : rejected) += 1;
    }
    // Every plane of the crown comes from a kept normal: no outward-octant violation.
    for (const HalfSpace& hs : c.planes) {
      bool found = false;
      for (const FgNormal& n : c.history)
        if (n.kept && glm::all(glm::equal(n.direction, hs.normal))) found = true;
      EXPECT_TRUE(found);
    }
    EXPECT_LE(c.planes.size(), 6u << 3);
  }
  EXPECT_GT(rejected, 0u);  // the rule is exercised
  EXPECT_GT(kept, rejected);
}

TEST(FournierGrindal, SameSeedSameCrown) {
  const FournierGrindalParams p = octahedron();
  const FgCrown a = make_fournier_grindal_crown(p, 5), b = make_fournier_grindal_crown(p, 5),
                c = make_fournier_grindal_crown(p, 6);
  ASSERT_EQ(a.planes.size(), b.planes.size());
  for (size_t i = 0; i < a.planes.size(); ++i) {
    EXPECT_EQ(a.planes[i].normal, b.planes[i].normal);
    EXPECT_EQ(a.planes[i].offset, b.planes[i].offset);
  }
  EXPECT_TRUE(a.planes.size() != c.planes.size() || a.planes[0].offset != c.planes[0].offset);
}

TEST(FournierGrindal, TreeHasCrownAboveHexagonalTrunk) {
  FournierGrindalParams p = octahedron();
  p.crown_base_m = 3.0f;
  const TreeModel m = make_fournier_grindal_tree(p, 2);
  ASSERT_EQ(m.solids.size(), 2u);
  const HalfSpaceSolid& trunk = m.solids[0];
  const HalfSpaceSolid& crown = m.solids[1];
  EXPECT_EQ(trunk.material_slot, 0);
  EXPECT_EQ(crown.material_slot, 1);
  EXPECT_EQ(trunk.planes.size(), 8u);  // six sides and two caps
  EXPECT_NEAR(crown.bounds.lo.z, 3.0f, 0.01f);
  EXPECT_NEAR(trunk.bounds.lo.z, 0.0f, 0.01f);
  EXPECT_GT(trunk.bounds.hi.z, 3.0f);  // reaches into the crown
  EXPECT_LT(trunk.bounds.hi.z, crown.bounds.hi.z);
  // The trunk's cross-section at the base is a hexagon of apothem trunk_radius (along x) and
  // circumradius trunk_radius / cos 30° (along y); bounds are padded by about a millimetre.
  EXPECT_NEAR(trunk.bounds.hi.x, p.trunk_radius_m, 2e-3f);
  EXPECT_NEAR(trunk.bounds.hi.y, p.trunk_radius_m / std::cos(std::numbers::pi_v<float> / 6), 2e-3f);
}

TEST(FournierGrindal, UnboundedInitialNormalsAreAnError) {
  FournierGrindalParams p;
  p.normals = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // an open octant
  p.generations = 0;
  EXPECT_THROW(make_fournier_grindal_tree(p, 1), Error);
}

TEST(FournierGrindal, BarkPaletteIsBasePlusRange) {
  FournierGrindalParams p;
  p.bark_rgb = Vec3(60, 30, 10) / 255.0f;  // §5's example
  p.bark_range_rgb = Vec3(40, 20, 10) / 255.0f;
  const std::vector<Vec3> palette = fournier_grindal_bark_palette(p, 3);
  ASSERT_EQ(palette.size(), size_t(kFournierGrindalBarkColours));
  for (const Vec3& c : palette)
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(c[k], p.bark_rgb[k]);
      EXPECT_LE(c[k], p.bark_rgb[k] + p.bark_range_rgb[k]);
    }
  EXPECT_NE(palette[0], palette[1]);
}

}  // namespace
}  // namespace sylva
