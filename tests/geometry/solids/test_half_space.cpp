// Half-space solids (geometry/solids/half_space.h): exact ray clipping against a brute-force
// reference, bounds, rays from inside, grazing rays at edges and vertices, the displaced surface's
// sphere tracer (against dense sampling, continuity across viewpoints), face extraction and volume.

#include "core/rng.h"
#include "geometry/solids/half_space.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sylva {
namespace {

// A random convex polytope: `n` planes tangent to a unit-ish ellipsoid (a = 3, 2, 4 m).
ConvexPolytope random_polytope(int n, uint64_t seed) {
  Pcg32 rng(seed);
  ConvexPolytope planes;
  for (int i = 0; i < n; ++i) {
    const float z = rng.symmetric(), phi = 2.0f * std::numbers::pi_v<float> * rng.uniform();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const Vec3 u(r * std::cos(phi), r * std::sin(phi), z);
    const Vec3 axes(3.0f, 2.0f, 4.0f);
    planes.push_back(HalfSpace{u, glm::length(u * axes) * rng.uniform(0.9f, 1.1f)});
  }
  return planes;
}

Vec3 random_direction(Pcg32& rng) {
  const float z = rng.symmetric(), phi = 2.0f * std::numbers::pi_v<float> * rng.uniform();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Brute force: the first t on a dense grid where every plane holds.
double reference_entry(const ConvexPolytope& planes, const Vec3& o, const Vec3& d, double t_lo, double t_hi,
                       int steps) {
  for (int i = 0; i <= steps; ++i) {
    const double t = t_lo + (t_hi - t_lo) * i / steps;
    if (polytope_distance(planes, o + static_cast<float>(t) * d) <= 0.0f) return t;
  }
  return std::numeric_limits<double>::infinity();
}

HalfSpaceSolid solid_of(ConvexPolytope planes, float displacement = 0.0f) {
  HalfSpaceSolid s;
  s.planes = std::move(planes);
  s.displacement_m = displacement;
  s.displacement = FbmParams{0.6f, 2.0f, 4, 1.5f, 7};
  finish_solid(s);
  return s;
}

TEST(HalfSpace, ClipMatchesBruteForceOnRandomRays) {
  const HalfSpaceSolid solid = solid_of(random_polytope(40, 3));
  Pcg32 rng(11);
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 o = random_direction(rng) * 12.0f;
    const Vec3 d = glm::normalize(Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric()) * 3.0f - o);
    const int steps = 20000;
    const double ref = reference_entry(solid.planes, o, d, 0.0, 30.0, steps);
    SolidHit hit;
    const bool found = intersect_solid(solid, o, d, 0.0f, 1e30f, &hit);
    if (!std::isfinite(ref)) {
      // The grid may step over a sliver near the silhouette; a reported hit must then be on it.
      if (found) {
        EXPECT_NEAR(polytope_distance(solid.planes, o + hit.t * d), 0.0f, 1e-4f);
      }
      continue;
    }
    ASSERT_TRUE(found) << "ray " << i;
    ++hits;
    EXPECT_LE(hit.t, ref + 1e-4);
    EXPECT_GE(hit.t, ref - 30.0 / steps - 1e-4);
    // The normal is the plane the ray crosses: just before the hit that plane is the most violated.
    const Vec3 before = o + (hit.t - 1e-3f) * d;
    float worst = -1e30f;
    Vec3 worst_normal(0.0f);
    for (const HalfSpace& hs : solid.planes)
      if (glm::dot(hs.normal, before) - hs.offset > worst) {
        worst = glm::dot(hs.normal, before) - hs.offset;
        worst_normal = hs.normal;
      }
    EXPECT_GT(glm::dot(worst_normal, hit.normal), 0.999f);
    EXPECT_LT(glm::dot(hit.normal, d), 0.0f);
  }
  EXPECT_GT(hits, 100);
}

TEST(HalfSpace, BoundsContainEveryHit) {
  for (const float displacement : {0.0f, 0.4f}) {
    const HalfSpaceSolid solid = solid_of(random_polytope(30, 5), displacement);
    Pcg32 rng(13);
    for (int i = 0; i < 300; ++i) {
      const Vec3 o = random_direction(rng) * 15.0f;
      const Vec3 d = glm::normalize(random_direction(rng) * 4.0f - o);
      SolidHit hit;
      if (!intersect_solid(solid, o, d, 0.0f, 1e30f, &hit)) continue;
      const Vec3 p = o + hit.t * d;
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(p[k], solid.bounds.lo[k]);
        EXPECT_LE(p[k], solid.bounds.hi[k]);
      }
    }
  }
}

TEST(HalfSpace, RaysFromInsideHitTheExitFace) {
  const HalfSpaceSolid solid = solid_of(random_polytope(40, 9));
  Pcg32 rng(17);
  for (int i = 0; i < 200; ++i) {
    const Vec3 o = random_direction(rng) * 0.5f;
    ASSERT_LT(polytope_distance(solid.planes, o), 0.0f);
    const Vec3 d = random_direction(rng);
    SolidHit hit;
    ASSERT_TRUE(intersect_solid(solid, o, d, 0.0f, 1e30f, &hit));
    EXPECT_GT(hit.t, 0.0f);
    EXPECT_NEAR(polytope_distance(solid.planes, o + hit.t * d), 0.0f, 1e-5f);
    EXPECT_GT(glm::dot(hit.normal, d), 0.0f);
    // t_max before the exit: no hit.
    EXPECT_FALSE(intersect_solid(solid, o, d, 0.0f, 0.99f * hit.t, &hit));
  }
}

TEST(HalfSpace, GrazingRaysAtEdgesAndVertices) {
  const HalfSpaceSolid solid = solid_of(random_polytope(25, 21));
  const PolytopeFaces faces = polytope_faces(solid.planes, 100.0f);
  Vec3 centre(0.0f);
  int n = 0;
  for (const auto& poly : faces.polygons)
    for (const Vec3& v : poly) {
      centre += v;
      ++n;
    }
  centre /= static_cast<float>(n);
  Pcg32 rng(23);
  int tested = 0;
  for (const auto& poly : faces.polygons)
    for (size_t k = 0; k < poly.size(); ++k) {
      // A vertex and an edge midpoint, pulled a hair into the solid: rays aimed at them hit, at them.
      for (const Vec3& target : {poly[k], 0.5f * (poly[k] + poly[(k + 1) % poly.size()])}) {
        const Vec3 inside = target + 1e-4f * (centre - target);
        const Vec3 o = inside + random_direction(rng) * 20.0f;
        if (polytope_distance(solid.planes, o) <= 0.0f) continue;
        const Vec3 d = glm::normalize(inside - o);
        SolidHit hit;
        ASSERT_TRUE(intersect_solid(solid, o, d, 0.0f, 1e30f, &hit));
        EXPECT_LE(hit.t, glm::length(inside - o) + 1e-3f);
        EXPECT_NEAR(polytope_distance(solid.planes, o + hit.t * d), 0.0f, 1e-4f);
        // Aimed at the vertex itself, pulled a hair outwards: a miss or a hit right there.
        const Vec3 outside = target - 1e-3f * (centre - target);
        const Vec3 d2 = glm::normalize(outside - o);
        if (intersect_solid(solid, o, d2, 0.0f, 1e30f, &hit)) {
          EXPECT_NEAR(polytope_distance(solid.planes, o + hit.t * d2), 0.0f, 1e-4f);
        }
        ++tested;
      }
    }
  EXPECT_GT(tested, 50);
}

TEST(HalfSpace, FacesVolumeOfACube) {
  ConvexPolytope cube;
  for (int axis = 0; axis < 3; ++axis)
    for (const float s : {-1.0f, 1.0f}) {
      Vec3 n(0.0f);
      n[axis] = s;
      cube.push_back(HalfSpace{n, axis == 2 ? 2.0f : 1.0f});
    }
  cube.push_back(HalfSpace{glm::normalize(Vec3(1, 1, 1)), 10.0f});  // redundant
  const PolytopeFaces faces = polytope_faces(cube, 100.0f);
  EXPECT_TRUE(faces.bounded);
  EXPECT_EQ(faces.polygons.size(), 6u);
  EXPECT_NEAR(polytope_volume(faces), 2.0 * 2.0 * 4.0, 1e-4);
  // The corner (1, 1, 2) cut off by x + y + z ≤ 3: a tetrahedron of legs 1 removed, a seventh face.
  cube.push_back(HalfSpace{glm::normalize(Vec3(1, 1, 1)), std::sqrt(3.0f)});
  const PolytopeFaces cut = polytope_faces(cube, 100.0f);
  EXPECT_EQ(cut.polygons.size(), 7u);
  EXPECT_NEAR(polytope_volume(cut), 16.0 - 1.0 / 6.0, 1e-3);
  // Without the bottom the region is unbounded.
  ConvexPolytope open(cube.begin(), cube.begin() + 4);
  EXPECT_FALSE(polytope_faces(open, 100.0f).bounded);
}

TEST(DisplacedSolid, SphereTracerMatchesDenseSampling) {
  const HalfSpaceSolid solid = solid_of(random_polytope(30, 31), 0.5f);
  Pcg32 rng(37);
  int agree = 0, hits = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 o = random_direction(rng) * 15.0f;
    const Vec3 d = glm::normalize(random_direction(rng) * 3.0f - o);
    // Dense reference: the first sign change of D on a grid of 1 mm.
    double ref = std::numeric_limits<double>::infinity();
    for (double t = 5.0; t < 25.0; t += 1e-3)
      if (solid_distance(solid, o + static_cast<float>(t) * d) < 0.0f) {
        ref = t;
        break;
      }
    SolidHit hit;
    const bool found = intersect_solid(solid, o, d, 0.0f, 1e30f, &hit);
    if (std::isfinite(ref)) {
      ++hits;
      if (found && std::abs(hit.t - ref) < 2e-3) ++agree;
      // The tracer never steps past the first crossing by more than the grid.
      if (found) {
        EXPECT_LT(hit.t, ref + 2e-3);
      }
    }
    if (found) {
      EXPECT_NEAR(solid_distance(solid, o + hit.t * d), 0.0f, 1e-3f);
    }
  }
  EXPECT_GT(hits, 60);
  EXPECT_GE(agree, hits - 1);
}

TEST(DisplacedSolid, SameHitFromTwoViewpoints) {
  const HalfSpaceSolid solid = solid_of(random_polytope(30, 41), 0.5f);
  Pcg32 rng(43);
  int same = 0, total = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 o = random_direction(rng) * 15.0f;
    const Vec3 d = glm::normalize(random_direction(rng) * 3.0f - o);
    SolidHit hit;
    if (!intersect_solid(solid, o, d, 0.0f, 1e30f, &hit)) continue;
    const Vec3 p = o + hit.t * d;
    // A second eye on the outside of the surface, looking at p.
    const Vec3 o2 = p + 3.0f * glm::normalize(hit.normal + 0.5f * random_direction(rng));
    const Vec3 d2 = glm::normalize(p - o2);
    SolidHit hit2;
    ASSERT_TRUE(intersect_solid(solid, o2, d2, 0.0f, 1e30f, &hit2));
    const float reach = glm::length(p - o2);
    ++total;
    // Either the same point, or something nearer hides it: never a hit behind p.
    EXPECT_LT(hit2.t, reach + 1e-3f);
    if (glm::length(o2 + hit2.t * d2 - p) < 1e-3f) ++same;
  }
  EXPECT_GT(total, 100);
  EXPECT_GT(same, total * 8 / 10);
}

}  // namespace
}  // namespace sylva
