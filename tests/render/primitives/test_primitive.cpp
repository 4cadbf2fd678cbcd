// The primitive kinds (render/primitives/): each kind's bounds hold every hit Embree finds on it and
// are tight to them, the scene's bounds are the kinds' (EmbreeScene::bounds), and each kind's
// validation names the prototype.

#include "core/error.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "geometry/grass.h"
#include "geometry/primitives.h"
#include "render/embree_scene.h"
#include "render/primitives/primitive.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include <string>

namespace sylva {
namespace {

// A cube [-1, 1]³ as an opaque half-space solid.
HalfSpaceSolid cube() {
  HalfSpaceSolid s;
  for (int axis = 0; axis < 3; ++axis)
    for (const float sign : {-1.0f, 1.0f}) {
      Vec3 n(0.0f);
      n[axis] = sign;
      s.planes.push_back(HalfSpace{n, 1.0f});
    }
  finish_solid(s);
  return s;
}

// One prototype of each kind, alone.
std::vector<std::pair<std::string, Prototype>> one_of_each_kind() {
  std::vector<std::pair<std::string, Prototype>> kinds;
  Prototype mesh;
  mesh.triangles = make_sphere(1.5f);
  kinds.emplace_back("triangles", std::move(mesh));
  // A cut-out leaf (its hits lie inside its quad) and an uncut one beside it (whose hits reach the
  // corners' box, so that the box's tightness is tested).
  Prototype leaves;
  for (const Vec3& c : {Vec3(0, 0, 0), Vec3(1, 0, 0.5f), Vec3(1, 1, 1), Vec3(0, 1, 0.2f)})
    leaves.leaves.corners.push_back(c);
  leaves.leaves.shapes.push_back(LeafShape::Oval);
  for (const Vec3& c : {Vec3(0.5f, 0, 0), Vec3(1.5f, 0, 0.5f), Vec3(1.5f, 1, 1), Vec3(0.5f, 1, 0.2f)})
    leaves.leaves.corners.push_back(c);
  leaves.leaves.shapes.push_back(LeafShape::Rectangle);
  kinds.emplace_back("leaf quads", std::move(leaves));
  Prototype solid;
  solid.solids.push_back(cube());
  solid.solid_palettes.push_back({0});
  kinds.emplace_back("solids", std::move(solid));
  Prototype ribbons;
  ribbons.curves = make_grass_patch(GrassParams{}, 3);
  kinds.emplace_back("ribbons", std::move(ribbons));
  Prototype exact;
  exact.curves = make_grass_patch(GrassParams{}, 4);
  exact.curves.exact = true;
  kinds.emplace_back("exact ribbons", std::move(exact));
  Prototype round;
  for (const Vec4& p :
       {Vec4(0, 0, 0, 0.05f), Vec4(0.2f, 0, 1, 0.04f), Vec4(0.5f, 0.3f, 2, 0.03f), Vec4(1, 1, 3, 0.02f)})
    round.curves.points.push_back(p);
  round.curves.round = true;
  kinds.emplace_back("round curves", std::move(round));
  Prototype discs;
  discs.discs.add(Vec3(0, 0, 1), 0.1f, glm::normalize(Vec3(0.3f, -0.2f, 1.0f)));
  discs.discs.add(Vec3(2, 1, 0), 0.2f, Vec3(1, 0, 0));
  discs.discs.add(Vec3(-1, 3, 2), 0.15f, glm::normalize(Vec3(1, 1, 1)));
  kinds.emplace_back("discs", std::move(discs));
  return kinds;
}

TEST(PrimitiveKinds, BoundsHoldEveryHitAndAreTight) {
  // Rays from all around at random points of each kind's box: every hit lies in the box (the
  // bounds are conservative for what Embree intersects, discs included, whose BVH box is their
  // sphere's), and the hits reach within 5 % of the box's size of each of its faces (tight). The
  // scene's bounds are the same box through the instance's transform (EmbreeScene::bounds).
  for (auto& [name, proto] : one_of_each_kind()) {
    Scene scene;
    scene.add_material("m", make_leaf("m", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.3f)));
    const uint32_t p = scene.add_prototype(std::move(proto));
    const Mat4 placed = glm::scale(glm::translate(Mat4(1.0f), Vec3(3, -2, 1)), Vec3(1.5f, 0.5f, 2.0f));
    scene.instances.push_back(Instance{p, placed});
    const Bounds3 ours = transformed(prototype_bounds(scene.prototypes[p]), placed);
    const EmbreeScene embree(scene);
    ASSERT_FALSE(ours.empty()) << name;
    const Vec3 size = ours.hi - ours.lo;
    const float ulps = 1e-5f * (1.0f + glm::length(ours.hi) + glm::length(ours.lo));
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(embree.bounds().lo[a], ours.lo[a], ulps) << name << " axis " << a;
      EXPECT_NEAR(embree.bounds().hi[a], ours.hi[a], ulps) << name << " axis " << a;
    }
    const Vec3 centre = 0.5f * (ours.lo + ours.hi);
    const float radius = glm::length(size) + 1.0f;
    Pcg32 rng(17);
    Bounds3 hits;
    for (int i = 0; i < 40000; ++i) {
      const Vec3 o = centre + radius * sample_uniform_sphere(uniform2(rng));
      const Vec3 target = ours.lo + uniform3(rng) * size;
      const Ray ray{o, glm::normalize(target - o)};
      RayHit hit;
      if (!embree.intersect(ray, &hit)) continue;
      const Vec3 at = ray.origin + hit.t * ray.direction;
      for (int a = 0; a < 3; ++a) {
        ASSERT_GE(at[a], ours.lo[a] - ulps) << name << " axis " << a;
        ASSERT_LE(at[a], ours.hi[a] + ulps) << name << " axis " << a;
      }
      hits.extend(at);
    }
    ASSERT_FALSE(hits.empty()) << name;
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(hits.lo[a] - ours.lo[a], 0.05f * glm::length(size)) << name << " axis " << a;
      EXPECT_LE(ours.hi[a] - hits.hi[a], 0.05f * glm::length(size)) << name << " axis " << a;
    }
  }
}

std::string validation_error(const Prototype& p) {
  try {
    validate_prototype(p);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(PrimitiveKinds, ValidationNamesThePrototype) {
  for (auto& [name, proto] : one_of_each_kind()) EXPECT_EQ(validation_error(proto), "") << name;
  Prototype p;
  p.name = "broken";
  p.triangles.positions = {Vec3(0.0f), Vec3(1.0f)};
  p.triangles.triangles = {glm::uvec3(0, 1, 2)};
  EXPECT_EQ(validation_error(p), "prototype 'broken': triangle 0 indexes a missing vertex");
  p.triangles = {};
  p.leaves.shapes = {LeafShape::Oval};
  EXPECT_EQ(validation_error(p), "prototype 'broken': leaf quads need 4 corners per leaf");
  p.leaves = {};
  p.solids.push_back(cube());
  EXPECT_EQ(validation_error(p), "prototype 'broken': every solid needs a material palette");
  p.solids = {};
  p.curves.points = {Vec4(0.0f), Vec4(0.0f), Vec4(0.0f), Vec4(0.0f)};
  p.curves.round = false;
  EXPECT_EQ(validation_error(p), "prototype 'broken': curves need 4 control points each and, unless round, 4 normals");
  p.curves = {};
  p.discs.centre = {Vec3(0.0f)};
  EXPECT_EQ(validation_error(p), "prototype 'broken': leaf discs need a radius and a normal each");
}

}  // namespace
}  // namespace sylva
