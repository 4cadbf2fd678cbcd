// Leaf outlines through the Embree scene: closest-hit and shadow rays pass a leaf quad's cut-out and
// stop on its blade, whether every leaf of a prototype has one outline (read once per geometry) or
// each leaf its own (read per leaf).

#include "core/error.h"
#include "geometry/leaf_shape.h"
#include "render/embree_scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

namespace sylva {
namespace {

// Unit leaf quads in the plane z = 0, leaf i over [2i, 2i + 1] × [0, 1] (u along x, v along y).
Prototype quads(const std::vector<LeafShape>& shapes) {
  Prototype p;
  p.name = "quads";
  for (size_t i = 0; i < shapes.size(); ++i) {
    const float x = 2.0f * static_cast<float>(i);
    for (const Vec3& c : {Vec3(x, 0, 0), Vec3(x + 1, 0, 0), Vec3(x + 1, 1, 0), Vec3(x, 1, 0)})
      p.leaves.corners.push_back(c);
    p.leaves.shapes.push_back(shapes[i]);
  }
  return p;
}

// The scene: the prototype placed once, 1 m up.
Scene scene_of(const std::vector<LeafShape>& shapes) {
  Scene s;
  s.add_material("leaf", make_leaf("leaf", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.3f)));
  s.instances.push_back({s.add_prototype(quads(shapes)), glm::translate(Mat4(1.0f), Vec3(0, 0, 1)), 0});
  return s;
}

// What a ray straight down through point (u, v) of leaf i meets: a closest hit on that leaf, and
// whether a shadow ray along it is blocked; both must agree.
bool blocked(const EmbreeScene& embree, int leaf, float u, float v) {
  const Vec3 origin(2.0f * static_cast<float>(leaf) + u, v, 3.0f);
  const Vec3 down(0, 0, -1);
  RayHit hit;
  const bool found = embree.intersect(Ray{origin, down}, &hit);
  const bool occluded = embree.occluded(origin, down, std::numeric_limits<float>::infinity());
  EXPECT_EQ(found, occluded) << "leaf " << leaf << " at (" << u << ", " << v << ")";
  if (found) {
    EXPECT_EQ(hit.kind, PrimitiveKind::kLeafQuads);
    EXPECT_EQ(hit.primitive, static_cast<uint32_t>(leaf));
    EXPECT_NEAR(hit.t, 2.0f, 1e-5f);
    EXPECT_NEAR(hit.u, u, 1e-5f);
    EXPECT_NEAR(hit.v, v, 1e-5f);
  }
  return found;
}

// A 10 × 10 grid over the unit square; points within 0.005 of the outline, where the ray's
// barycentrics may round either way, are left out. Both verdicts must occur.
void expect_outline(const EmbreeScene& embree, int leaf, LeafShape shape) {
  int inside = 0, outside = 0;
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 10; ++i) {
      const float u = 0.05f + 0.1f * static_cast<float>(i), v = 0.05f + 0.1f * static_cast<float>(j);
      const bool in = leaf_shape_inside(shape, u, v);
      bool near_edge = false;
      for (const Vec2 d : {Vec2(0.005f, 0), Vec2(-0.005f, 0), Vec2(0, 0.005f), Vec2(0, -0.005f)})
        near_edge = near_edge || leaf_shape_inside(shape, u + d.x, v + d.y) != in;
      if (near_edge) continue;
      (in ? inside : outside) += 1;
      EXPECT_EQ(blocked(embree, leaf, u, v), in)
          << leaf_shape_name(shape) << " leaf " << leaf << " at (" << u << ", " << v << ")";
    }
  EXPECT_GT(inside, 10) << leaf_shape_name(shape);
  EXPECT_GT(outside, shape == LeafShape::Rectangle ? -1 : 3) << leaf_shape_name(shape);
}

TEST(LeafOutlines, OneOutlineForAllLeavesCutsEveryLeaf) {
  for (const LeafShape shape : {LeafShape::Oval, LeafShape::Maple5, LeafShape::RightTriangle}) {
    const Scene scene = scene_of({shape, shape, shape});
    const EmbreeScene embree(scene, BvhBuild::kFast);
    for (int leaf = 0; leaf < 3; ++leaf) expect_outline(embree, leaf, shape);
  }
}

TEST(LeafOutlines, MixedOutlinesCutEachLeafByItsOwn) {
  const std::vector<LeafShape> shapes = {LeafShape::Rectangle, LeafShape::Oval, LeafShape::Triangle,
                                         LeafShape::RightTriangle, LeafShape::Oval};
  const Scene scene = scene_of(shapes);
  const EmbreeScene embree(scene, BvhBuild::kFast);
  for (size_t leaf = 0; leaf < shapes.size(); ++leaf) expect_outline(embree, static_cast<int>(leaf), shapes[leaf]);
  // A corner is blade on the rectangle and a cut-out on the oval beside it.
  EXPECT_TRUE(blocked(embree, 0, 0.03f, 0.03f));
  EXPECT_FALSE(blocked(embree, 1, 0.03f, 0.03f));
}

// Every instruction set Embree may run (capped at each in turn; the processor's widest at most)
// cuts the same outlines, on closest-hit and shadow rays.
TEST(LeafOutlines, EveryEmbreeInstructionSetCutsTheSame) {
  const std::vector<LeafShape> shapes = {LeafShape::Oval, LeafShape::Maple5, LeafShape::RightTriangle};
  const Scene scene = scene_of(shapes);
  for (const EmbreeIsa isa : {EmbreeIsa::kNative, EmbreeIsa::kSse2, EmbreeIsa::kSse42, EmbreeIsa::kAvx,
                              EmbreeIsa::kAvx2, EmbreeIsa::kAvx512}) {
    SCOPED_TRACE(embree_isa_name(isa));
    const EmbreeScene embree(scene, BvhBuild::kFast, isa);
    EXPECT_EQ(embree.stats().isa, resolve_embree_isa(isa));
    for (size_t leaf = 0; leaf < shapes.size(); ++leaf) expect_outline(embree, static_cast<int>(leaf), shapes[leaf]);
  }
}

TEST(EmbreeIsa, NamesParseAndCapsResolveAtMostTheProcessorsWidest) {
  const EmbreeIsa native = resolve_embree_isa(EmbreeIsa::kNative);
  EXPECT_NE(native, EmbreeIsa::kNative);
  for (const EmbreeIsa isa : {EmbreeIsa::kNative, EmbreeIsa::kSse2, EmbreeIsa::kSse42, EmbreeIsa::kAvx,
                              EmbreeIsa::kAvx2, EmbreeIsa::kAvx512}) {
    EXPECT_EQ(parse_embree_isa(embree_isa_name(isa)), isa);
    if (isa == EmbreeIsa::kNative) continue;
    EXPECT_LE(resolve_embree_isa(isa), isa) << embree_isa_name(isa);
    EXPECT_LE(resolve_embree_isa(isa), native) << embree_isa_name(isa);
  }
  EXPECT_EQ(resolve_embree_isa(EmbreeIsa::kSse2), EmbreeIsa::kSse2);  // every x86-64 processor has it
  try {
    parse_embree_isa("avx3");
    FAIL() << "accepted avx3";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("\"avx512\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sylva
