// Half-space solids through Embree (render/embree_scene.cpp user geometry): instanced closest hits
// and occlusion agree with intersect_solid in object space, for exact and displaced crowns.

#include "core/rng.h"
#include "geometry/trees/fournier_grindal/fournier_grindal.h"
#include "render/embree_scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

namespace sylva {
namespace {

TEST(EmbreeSolids, InstancedHitsMatchDirectIntersection) {
  for (const float displacement : {0.0f, 0.3f}) {
    FournierGrindalParams fg;
    fg.normals = {{2, 0, 0}, {-2, 0, 0}, {0, 2, 0}, {0, -2, 0}, {0, 0, 3}, {0, 0, -1.5f}};
    fg.displacement_m = displacement;
    Scene scene;
    Prototype p;
    p.solids = make_fournier_grindal_tree(fg, 9).solids;
    p.solid_palettes.assign(p.solids.size(), {0u});
    scene.add_prototype(p);
    const Mat4 xf = glm::scale(glm::rotate(glm::translate(Mat4(1.0f), Vec3(3, -1, 0)), 0.7f, Vec3(0, 0, 1)),
                               Vec3(1.5f, 1.5f, 2.0f));
    scene.instances.push_back({0, xf, 0});
    const EmbreeScene embree(scene);
    EXPECT_EQ(embree.stats().solids, 2u);
    const Mat4 inv = glm::inverse(xf);
    Pcg32 rng(5);
    int hits = 0;
    for (int i = 0; i < 400; ++i) {
      const Vec3 o = Vec3(3, -1, 4) + 25.0f * glm::normalize(Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric()));
      const Vec3 target = Vec3(3, -1, 5) + Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric()) * 5.0f;
      const Vec3 d = glm::normalize(target - o);
      // The reference: the nearest solid hit in object space (same t, affine map).
      const Vec3 oo = Vec3(inv * Vec4(o, 1.0f)), od = Vec3(inv * Vec4(d, 0.0f));
      float best = std::numeric_limits<float>::infinity();
      uint32_t best_prim = 0;
      Vec3 best_normal(0.0f);
      for (size_t k = 0; k < p.solids.size(); ++k) {
        SolidHit h;
        if (intersect_solid(p.solids[k], oo, od, 0.0f, best, &h)) {
          best = h.t;
          best_prim = static_cast<uint32_t>(k);
          best_normal = h.normal;
        }
      }
      RayHit hit;
      const bool found = embree.intersect(Ray{o, d}, &hit);
      ASSERT_EQ(found, std::isfinite(best)) << "ray " << i;
      EXPECT_EQ(embree.occluded(o, d, std::numeric_limits<float>::infinity()), found);
      if (!found) continue;
      ++hits;
      EXPECT_TRUE(hit.solid);
      EXPECT_FALSE(hit.leaf);
      EXPECT_EQ(hit.instance, 0u);
      EXPECT_EQ(hit.primitive, best_prim);
      EXPECT_NEAR(hit.t, best, 1e-3f * best);
      EXPECT_GT(glm::dot(hit.normal, best_normal), 0.999f);
      // Occlusion stops short of the hit: nothing in front.
      EXPECT_FALSE(embree.occluded(o, d, 0.99f * hit.t));
    }
    EXPECT_GT(hits, 100);
  }
}

}  // namespace
}  // namespace sylva
