// The primitive kinds (render/primitives/): each kind's bounds hold what Embree builds from it (the
// scene's bounds lie inside prototype_bounds; discs the other way round: Embree bounds a disc by
// its sphere) and are tight to it, and each kind's validation names the prototype.

#include "core/error.h"
#include "geometry/grass.h"
#include "geometry/primitives.h"
#include "render/embree_scene.h"
#include "render/primitives/primitive.h"

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
  Prototype leaves;
  for (const Vec3& c : {Vec3(0, 0, 0), Vec3(1, 0, 0.5f), Vec3(1, 1, 1), Vec3(0, 1, 0.2f)})
    leaves.leaves.corners.push_back(c);
  leaves.leaves.shapes.push_back(LeafShape::Oval);
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

TEST(PrimitiveKinds, BoundsHoldWhatEmbreeBuildsAndAreTight) {
  for (auto& [name, proto] : one_of_each_kind()) {
    Scene scene;
    scene.add_material("m", make_leaf("m", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.3f)));
    const uint32_t p = scene.add_prototype(std::move(proto));
    scene.instances.push_back(Instance{p});
    const Bounds3 ours = prototype_bounds(scene.prototypes[p]);
    const Bounds3 embree = EmbreeScene(scene).bounds();
    ASSERT_FALSE(ours.empty()) << name;
    ASSERT_FALSE(embree.empty()) << name;
    const Vec3 size = ours.hi - ours.lo;
    const float ulps = 1e-6f * (1.0f + glm::length(size));
    // Embree bounds a disc by its sphere (centre ± r); ours are the disc's exact box, inside it.
    const bool discs = name == "discs";
    const Bounds3& outer = discs ? embree : ours;
    const Bounds3& inner = discs ? ours : embree;
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(outer.lo[a], inner.lo[a] + ulps) << name << " axis " << a;
      EXPECT_GE(outer.hi[a], inner.hi[a] - ulps) << name << " axis " << a;
      // Tight: within 5 % of the kind's extent of each other (curves' control polygons reach beyond
      // a bent blade; a disc's sphere beyond the disc).
      EXPECT_LE(inner.lo[a] - outer.lo[a], 0.05f * glm::length(size)) << name << " axis " << a;
      EXPECT_LE(outer.hi[a] - inner.hi[a], 0.05f * glm::length(size)) << name << " axis " << a;
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
