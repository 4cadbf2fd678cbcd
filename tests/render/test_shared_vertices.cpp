// Vertex arrays shared with Embree (render/scene.h pad_for_vector_loads, EmbreeScene): prototypes
// added to a scene keep one zeroed spare element, Embree reads their vertices in place instead of a
// copy, and the hits and images are the same bits as with copied buffers.

#include "render_test_scenes.h"

#include "render/embree_scene.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sylva::test {
namespace {

TEST(SharedVertices, PaddingLeavesExactlyOneSpareElement) {
  std::vector<Vec3> slack;
  slack.reserve(100);
  for (int i = 0; i < 10; ++i) slack.push_back(Vec3(static_cast<float>(i), 1.0f, -2.0f));
  const std::vector<Vec3> before = slack;
  pad_for_vector_loads(slack);
  EXPECT_EQ(slack, before);
  EXPECT_EQ(slack.capacity(), slack.size() + 1);  // the slack beyond one element is shed

  std::vector<Vec3> exact = before;
  exact.shrink_to_fit();
  ASSERT_EQ(exact.capacity(), exact.size());
  pad_for_vector_loads(exact);
  EXPECT_EQ(exact, before);
  EXPECT_EQ(exact.capacity(), exact.size() + 1);

  const Vec3* storage = exact.data();
  pad_for_vector_loads(exact);  // already padded: kept in place
  EXPECT_EQ(exact.data(), storage);
  EXPECT_EQ(exact, before);

  std::vector<Vec3> empty;
  pad_for_vector_loads(empty);
  EXPECT_TRUE(empty.empty());
}

// Bytes of the vertex arrays Embree can share: mesh positions and leaf corners.
size_t vertex_bytes(const Scene& s) {
  size_t bytes = 0;
  for (const Prototype& p : s.prototypes)
    bytes += (p.triangles.positions.size() + p.leaves.corners.size()) * sizeof(Vec3);
  return bytes;
}

Image render(const Scene& scene, const EmbreeScene& embree) {
  RenderSettings settings = test_settings(48, 32, 8, 16);
  settings.seed = 5;
  Renderer r(scene, embree, settings);
  Film film = r.make_film();
  r.render(film);
  return r.make_image(film);
}

TEST(SharedVertices, SharedBuffersTraceTheSameBitsAsCopies) {
  const Scene shared = small_forest_scene();
  Scene copied = shared;
  for (Prototype& p : copied.prototypes) {
    p.triangles.positions.shrink_to_fit();
    p.leaves.corners.shrink_to_fit();
    ASSERT_EQ(p.triangles.positions.capacity(), p.triangles.positions.size());
    ASSERT_EQ(p.leaves.corners.capacity(), p.leaves.corners.size());
  }
  const EmbreeScene shared_embree(shared), copied_embree(copied);
  ASSERT_GT(vertex_bytes(shared), 0u);
  EXPECT_EQ(shared_embree.stats().shared_vertex_bytes, vertex_bytes(shared));
  EXPECT_EQ(copied_embree.stats().shared_vertex_bytes, 0u);
  // The copies are Embree's own memory: its monitor counts them, not the shared arrays.
  EXPECT_GE(copied_embree.stats().bvh_bytes, shared_embree.stats().bvh_bytes + vertex_bytes(shared));

  // Rays through the leaf clouds and onto the ground: the same hits, to the bit.
  int leaf_hits = 0, ground_hits = 0;
  for (int i = 0; i < 400; ++i) {
    const float a = 0.0157f * static_cast<float>(i);
    const Ray ray{Vec3(0.0f, -5.0f, 1.5f), Vec3(std::sin(a) * 0.6f, 1.0f, std::cos(3.0f * a) * 0.4f - 0.1f), 1e30f};
    RayHit hs, hc;
    const bool s = shared_embree.intersect(ray, &hs), c = copied_embree.intersect(ray, &hc);
    ASSERT_EQ(s, c) << "ray " << i;
    if (!s) continue;
    EXPECT_EQ(hs.t, hc.t) << "ray " << i;
    EXPECT_EQ(hs.u, hc.u) << "ray " << i;
    EXPECT_EQ(hs.v, hc.v) << "ray " << i;
    EXPECT_EQ(hs.primitive, hc.primitive) << "ray " << i;
    EXPECT_EQ(hs.instance, hc.instance) << "ray " << i;
    EXPECT_EQ(hs.kind, hc.kind) << "ray " << i;
    (hs.kind == PrimitiveKind::kLeafQuads ? leaf_hits : ground_hits) += 1;
  }
  EXPECT_GT(leaf_hits, 20);
  EXPECT_GT(ground_hits, 20);
  EXPECT_TRUE(same_bits(render(shared, shared_embree), render(copied, copied_embree)));
}

}  // namespace
}  // namespace sylva::test
