// The instance levels (render/embree_scene.h, Scene::instance_level): placed copies as one Embree
// user geometry (the array), or traced by the sweep instead of Embree's instance BVH, give the same
// hits, labels and images as Embree's native instances, in world units under scaled transforms,
// deterministically, in bounded memory.

#include "render_test_scenes.h"

#include "geometry/grass.h"
#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/weber_penn/weber_penn.h"
#include "render/embree_scene.h"
#include "tests/geometry/trees/wp_test_species.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>

namespace sylva::test {
namespace {

constexpr int kW = 96, kH = 54;
// Sidak threshold for alpha = 0.01 over kW·kH·4 pixel-channels: |z| > 5.0 (two-sided).
constexpr double kPixelZ = 5.0;

TEST(InstanceArray, AutomaticLevelSwitchesAtTheThreshold) {
  Scene s;
  s.prototypes.resize(1);
  s.instances.resize(kInstanceArrayThreshold - 1);
  EXPECT_FALSE(uses_instance_array(s));
  s.instances.resize(kInstanceArrayThreshold);
  EXPECT_TRUE(uses_instance_array(s));
  s.instance_level = InstanceLevel::native;
  EXPECT_FALSE(uses_instance_array(s));
  s.instances.resize(2);
  s.instance_level = InstanceLevel::array;
  EXPECT_TRUE(uses_instance_array(s));
  // A cyclic plot counts its nine copies of every instance.
  s.instance_level = InstanceLevel::automatic;
  s.plot = PlotDesc{true, Vec2(-1.0f), Vec2(1.0f), true};
  s.instances.resize(kInstanceArrayThreshold / 9 + 1);
  EXPECT_TRUE(uses_instance_array(s));
  s.plot.cyclic = false;
  EXPECT_FALSE(uses_instance_array(s));
}

// Scaled copies: distances are world distances on both paths. A unit box (base on z = 0) scaled by
// 3 (x), 2 (y) and 4 (z) with its base at z = 1: a ray from above meets its top at z = 5.
TEST(InstanceArray, HitDistancesAreWorldDistancesUnderScale) {
  Scene s;
  Prototype box;
  box.triangles = make_box(Vec3(1.0f));
  s.add_prototype(std::move(box));
  const Mat4 placed = glm::scale(glm::translate(Mat4(1.0f), Vec3(10.0f, -3.0f, 1.0f)), Vec3(3.0f, 2.0f, 4.0f));
  s.instances.push_back({0, placed, 1});
  Bounds3 object;
  for (const Vec3& p : s.prototypes[0].triangles.positions) object.extend(p);
  const float top = 1.0f + 4.0f * object.hi.z;
  for (InstanceLevel level : {InstanceLevel::native, InstanceLevel::array, InstanceLevel::sweep}) {
    const Scene scene = with_level(s, level);
    const EmbreeScene embree(scene);
    EXPECT_EQ(embree.stats().instance_array, level == InstanceLevel::array);
    EXPECT_EQ(embree.stats().instance_sweep, level == InstanceLevel::sweep);
    RayHit hit;
    // Straight down onto the top face, and slanted (direction not normalised: t in its units).
    ASSERT_TRUE(embree.intersect(Ray{Vec3(10.5f, -3.2f, 20.0f), Vec3(0, 0, -1), 100.0f}, &hit));
    EXPECT_NEAR(hit.t, 20.0f - top, 1e-5f);
    EXPECT_EQ(hit.instance, 0u);
    ASSERT_TRUE(embree.intersect(Ray{Vec3(10.0f, -3.0f, 20.0f), Vec3(0.1f, 0.0f, -2.0f), 100.0f}, &hit));
    EXPECT_NEAR(hit.t, (20.0f - top) / 2.0f, 1e-5f);
    // Occlusion stops exactly there: free short of the top, blocked beyond it.
    EXPECT_FALSE(embree.occluded(Vec3(10.5f, -3.2f, 20.0f), Vec3(0, 0, -1), 20.0f - top - 1e-3f));
    EXPECT_TRUE(embree.occluded(Vec3(10.5f, -3.2f, 20.0f), Vec3(0, 0, -1), 20.0f - top + 1e-3f));
    // A miss beside the scaled box (it spans x in 10 ± 1.5 times the object half-width).
    EXPECT_FALSE(
        embree.intersect(Ray{Vec3(10.0f + 3.0f * object.hi.x + 0.01f, -3.0f, 20.0f), Vec3(0, 0, -1), 100.0f}, &hit));
    // Bounds of the scene: the scaled box (the array pads them by a few ulps only).
    EXPECT_NEAR(embree.bounds().hi.z, top, 1e-4f);
    EXPECT_NEAR(embree.bounds().lo.x, 10.0f + 3.0f * object.lo.x, 1e-4f);
  }
}

// Renders of the stand through native instances and through `level` (other seeds) agree, and the
// comparison has the power to see a fault inside the prototypes reached that way: shadow rays that
// ignore the leaf outlines (the golden suite's fault, render/testing/faults.h).
void expect_same_image(InstanceLevel level, const char* what) {
  const Scene s = stand_scene();
  const Image native = render_with(with_level(s, InstanceLevel::native), kW, kH, 48, 11);
  const Image other = render_with(with_level(s, level), kW, kH, 48, 12);
  const Agreement same = agreement(native, other, kPixelZ);
  std::printf("[instance levels] native vs %s: worst mean |z| %.2f, %d of %d pixel-channels reject\n", what,
              same.worst_mean_z, same.rejecting_pixels, same.pixel_channels);
  EXPECT_LT(same.worst_mean_z, 4.0);
  EXPECT_LE(same.rejecting_pixels, same.pixel_channels / 400);  // 0.25 %, as the golden checks
  TransportFaults faults;
  faults.no_shadow_alpha = true;
  const Agreement wrong = agreement(native, render_with(with_level(s, level), kW, kH, 48, 12, 0, faults), kPixelZ);
  std::printf("[instance levels] native vs %s without shadow alpha: worst mean |z| %.2f, %d pixel-channels reject\n",
              what, wrong.worst_mean_z, wrong.rejecting_pixels);
  EXPECT_TRUE(wrong.worst_mean_z >= 4.0 || wrong.rejecting_pixels > wrong.pixel_channels / 400);
}

TEST(InstanceArray, SameImageAsNativeInstances) { expect_same_image(InstanceLevel::array, "array"); }

// The first-hit labels and geometry AOVs come from one ray through each pixel centre: the same hit
// on both paths. Not bit for bit everywhere: Embree inverts a native instance's transform with its
// own approximate reciprocal, the array per hit with an exact float inverse, so the object-space
// rays differ in their last bits and a ray grazing an edge within those bits may go either way.
constexpr int kMaxLabelMismatches = kW * kH / 1000;

void expect_same_labels(const Scene& s, const char* what, InstanceLevel level = InstanceLevel::array) {
  const Image native = render_with(with_level(s, InstanceLevel::native), kW, kH, 1, 5);
  const Image array = render_with(with_level(s, level), kW, kH, 1, 5);
  for (const char* channel : {"id.instance", "id.object", "id.class", "id.variant"}) {
    const int n = label_mismatches(native, array, channel);
    std::printf("[instance array] %s %s: %d of %d pixels differ\n", what, channel, n, kW * kH);
    EXPECT_LE(n, kMaxLabelMismatches) << what << " " << channel;
  }
  // Depth (world units: the array moves the ray without renormalising it) and normals agree where
  // the same instance was hit.
  const int id = native.find_channel("id.instance"), z = native.find_channel("Z"), nx = native.find_channel("N.X");
  int hits = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (native.at(x, y, id) != array.at(x, y, id) || native.at(x, y, id) == 0) continue;
      ++hits;
      EXPECT_NEAR(native.at(x, y, z), array.at(x, y, z), 1e-4f * native.at(x, y, z)) << what << " " << x << "," << y;
      EXPECT_NEAR(native.at(x, y, nx), array.at(x, y, nx), 1e-3f) << what << " " << x << "," << y;
    }
  EXPECT_GT(hits, kW * kH / 2) << what;
  // And the labels are not trivial: trees, boxes and grass are all seen.
  const int cls = native.find_channel("id.class");
  bool grass = false, tree = false;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      grass = grass || native.at(x, y, cls) == kClassGrass;
      tree = tree || native.at(x, y, cls) == kFirstNamedClass + 1;
    }
  EXPECT_TRUE(grass && tree) << what;
}

TEST(InstanceArray, SameLabelsAsNativeInstances) { expect_same_labels(stand_scene(), "open"); }

// The sweep (render/instance_sweep.h) moves rays into object space as the array does: the same
// labels, depths and normals as Embree's instance BVH, up to the same grazing rays.
TEST(InstanceSweep, SameLabelsAsNativeInstances) { expect_same_labels(stand_scene(), "sweep", InstanceLevel::sweep); }

TEST(InstanceSweep, SameImageAsNativeInstances) { expect_same_image(InstanceLevel::sweep, "sweep"); }

TEST(InstanceSweep, BitIdenticalAtAnyThreadCount) {
  const Scene s = with_level(stand_scene(), InstanceLevel::sweep);
  const Image one = render_with(s, 48, 27, 4, 3, 1);
  EXPECT_TRUE(same_bits(one, render_with(s, 48, 27, 4, 3, 2)));
  EXPECT_TRUE(same_bits(one, render_with(s, 48, 27, 4, 3, 4)));
}

TEST(InstanceArray, SameLabelsInACyclicPlot) {
  Scene s = stand_scene();
  s.instances.erase(s.instances.begin());  // no ground plane larger than the period
  s.plot = PlotDesc{true, Vec2(-5.0f, -2.0f), Vec2(5.0f, 7.0f), true};
  Prototype floor;
  floor.triangles = make_plane(10, 9);
  floor.triangle_material = 0;
  s.instances.push_back(
      {s.add_prototype(std::move(floor)), glm::translate(Mat4(1.0f), Vec3(0, 2.5f, 0)), 0, kClassTerrain, 0});
  expect_same_labels(s, "cyclic");
}

TEST(InstanceArray, BitIdenticalAtAnyThreadCount) {
  const Scene s = with_level(stand_scene(), InstanceLevel::array);
  const Image one = render_with(s, 48, 27, 4, 3, 1);
  const Image two = render_with(s, 48, 27, 4, 3, 2);
  const Image four = render_with(s, 48, 27, 4, 3, 4);
  EXPECT_TRUE(same_bits(one, two));
  EXPECT_TRUE(same_bits(one, four));
}

// Memory per instance: Embree's share (its memory monitor: the top BVH and its build) for 10^5
// copies of a one-triangle prototype stays under kArrayInstanceBytes, the figure the pre-render
// memory estimate uses (Scene::instances and the per-prototype BVHs are counted apart).
TEST(InstanceArray, EmbreeBytesPerInstanceBounded) {
  Scene s;
  Prototype tri;
  tri.triangles.positions = {Vec3(0, 0, 0), Vec3(0.1f, 0, 0), Vec3(0, 0.1f, 0.1f)};
  tri.triangles.triangles = {glm::uvec3(0, 1, 2)};
  s.add_prototype(std::move(tri));
  constexpr int kCopies = 100000;
  s.instances.reserve(kCopies);
  for (int i = 0; i < kCopies; ++i)
    s.instances.push_back({0,
                           glm::rotate(glm::translate(Mat4(1.0f), Vec3(static_cast<float>(i % 316) * 0.5f,
                                                                       static_cast<float>(i / 316) * 0.5f, 0.0f)),
                                       0.1f * static_cast<float>(i % 61), Vec3(0, 0, 1)),
                           static_cast<uint32_t>(i + 1)});
  const EmbreeScene embree(s);
  ASSERT_TRUE(embree.stats().instance_array);
  const double per_instance = static_cast<double>(embree.stats().bvh_bytes) / kCopies;
  std::printf("[instance array] Embree bytes per instance: %.1f (bound %llu)\n", per_instance,
              static_cast<unsigned long long>(kArrayInstanceBytes));
  EXPECT_LE(per_instance, static_cast<double>(kArrayInstanceBytes));
  EXPECT_GT(per_instance, 8.0);  // the monitor does see the top BVH
  // Every copy is there: a ray down onto copy 12345's triangle hits it.
  const Vec3 p = Vec3(s.instances[12345].world_from_object * Vec4(0.02f, 0.02f, 0.0f, 1.0f));
  RayHit hit;
  ASSERT_TRUE(embree.intersect(Ray{p + Vec3(0, 0, 5.0f), Vec3(0, 0, -1), 10.0f}, &hit));
  EXPECT_EQ(hit.instance, 12345u);
}

// The pre-render memory estimate (docs/limits.md) counts grass curves and the instance level, and
// covers what Embree reports for a built scene of both.
TEST(InstanceArray, MemoryEstimateCountsCurvesAndInstances) {
  const RenderSettings settings = test_settings(8, 8, 1);
  Scene s;
  Prototype grass;
  GrassParams gp;
  gp.patch_size_m = 4.0f;
  grass.curves = make_grass_patch(gp, 3);
  const uint64_t curves = grass.curves.size();
  s.add_prototype(std::move(grass));
  const uint64_t empty = estimate_render_memory(s, settings).bvh_bytes;
  EXPECT_EQ(empty, curves * kBvhBytesPerCurve);
  for (int i = 0; i < 20000; ++i)
    s.instances.push_back({0, glm::translate(Mat4(1.0f), Vec3(4.0f * static_cast<float>(i % 150),
                                                              4.0f * static_cast<float>(i / 150), 0.0f))});
  const uint64_t array = estimate_render_memory(s, settings).bvh_bytes;
  EXPECT_EQ(array, empty + 20000 * kArrayInstanceBytes);
  s.instance_level = InstanceLevel::native;
  EXPECT_EQ(estimate_render_memory(s, settings).bvh_bytes, empty + 20000 * kNativeInstanceBytes);
  s.instance_level = InstanceLevel::automatic;
  const EmbreeScene embree(s);
  ASSERT_TRUE(embree.stats().instance_array);
  std::printf("[instance array] estimate %llu bytes, Embree %zu bytes\n", static_cast<unsigned long long>(array),
              embree.stats().bvh_bytes);
  EXPECT_GE(array, embree.stats().bvh_bytes);
}

// The estimate per primitive covers what Embree reports for leaf quads and paired stem triangles
// (one quad BVH per prototype): an upper bound, within twice the BVH (a leaf cloud's quads take
// 199 bytes each, a tree's stems, paired, less).
TEST(InstanceArray, MemoryEstimateCoversLeavesAndStems) {
  const RenderSettings settings = test_settings(8, 8, 1);
  Scene s;
  Prototype tree;
  TreeMesh mesh = make_tree_mesh(make_weber_penn_tree(quaking_aspen(), 4));
  tree.triangles = std::move(mesh.stems);
  tree.leaves = std::move(mesh.leaves);
  s.add_prototype(std::move(tree));
  Prototype cloud;
  cloud.leaves = make_leaf_cloud(LeafCloudParams{}, 5);
  s.add_prototype(std::move(cloud));
  for (uint32_t p = 0; p < 2; ++p) s.instances.push_back({p, glm::translate(Mat4(1.0f), Vec3(10.0f * p, 0, 0))});
  const uint64_t estimate = estimate_render_memory(s, settings).bvh_bytes;
  const EmbreeScene embree(s, BvhBuild::kFast);
  std::printf("[leaves and stems] estimate %llu bytes, Embree %zu bytes\n", static_cast<unsigned long long>(estimate),
              embree.stats().bvh_bytes);
  EXPECT_GE(estimate, embree.stats().bvh_bytes);
  EXPECT_LE(estimate, 2 * embree.stats().bvh_bytes);
}

}  // namespace
}  // namespace sylva::test
