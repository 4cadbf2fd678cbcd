// The renderer's API: regions and sample ranges, exact film merges (split by samples, by tiles and
// both, bit-identical to one render), one Embree scene shared by several renderers, the stem of a
// leaf recovered from a hit, and the triangle and barycentrics of a mesh hit.

#include "core/error.h"
#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/weber_penn/weber_penn.h"
#include "render/renderer.h"
#include "tests/geometry/trees/wp_test_species.h"
#include "tests/render/render_test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <thread>

namespace sylva {
namespace {

using test::film_bytes;
using test::same_bits;
using test::small_forest_scene;
using test::test_settings;

// 40×24 is not a whole number of 16-pixel tiles; 21 spp does not split evenly into 2 or 7 chunks.
constexpr int kWidth = 40, kHeight = 24, kSpp = 21, kDepth = 8;

class RendererApi : public ::testing::Test {
 protected:
  RendererApi()
      : scene_(small_forest_scene()),
        embree_(scene_),
        renderer_(scene_, embree_, test_settings(kWidth, kHeight, kSpp, kDepth)) {
    reference_ = renderer_.make_film();
    renderer_.render(reference_);
  }

  Scene scene_;
  EmbreeScene embree_;
  Renderer renderer_;
  Film reference_;  // one render of every pixel, samples [0, kSpp)
};

TEST_F(RendererApi, ChunkHelpersCoverTheInputInOrder) {
  for (int n : {1, 2, 3, 7, 30}) {
    uint32_t next = 5;
    int row = 3;
    for (int i = 0; i < n; ++i) {
      const SampleRange r = sample_chunk({5, 26}, i, n);
      EXPECT_EQ(r.first, next);
      EXPECT_LE(r.size(), 21u / n + 1);
      next = r.end;
      const PixelRegion band = row_chunk({2, 3, 9, 20}, i, n);
      EXPECT_EQ(band.y0, row);
      EXPECT_EQ(band.x0, 2);
      EXPECT_EQ(band.x1, 9);
      row = band.y1;
    }
    EXPECT_EQ(next, 26u);
    EXPECT_EQ(row, 20);
  }
  EXPECT_THROW(sample_chunk({0, 8}, 3, 3), Error);
  EXPECT_THROW(row_chunk({0, 0, 4, 4}, -1, 2), Error);
}

TEST_F(RendererApi, SampleChunksMergeBitIdenticalToOneRender) {
  const std::string expected = film_bytes(reference_);
  for (int n : {1, 2, 3, 7}) {
    std::vector<Film> chunks;
    for (int i = 0; i < n; ++i) {
      const SampleRange r = sample_chunk({0, kSpp}, i, n);
      chunks.push_back(renderer_.make_film(renderer_.image_region(), r.first));
      renderer_.render(chunks.back(), renderer_.image_region(), r);
      EXPECT_EQ(chunks.back().total_samples(), uint64_t{r.size()} * kWidth * kHeight);
      EXPECT_EQ(chunks.back().keeps_samples(), i > 0);
    }
    // Left to right: ((A + B) + C) + ...
    Film merged = chunks[0];
    for (int i = 1; i < n; ++i) merged.merge(chunks[i]);
    EXPECT_EQ(film_bytes(merged), expected) << n << " sample chunks";
    EXPECT_TRUE(same_bits(renderer_.make_image(merged), renderer_.make_image(reference_))) << n;
    // Right to left: A + (B + (C + ...)): the later chunks first, then onto the first.
    Film tail = chunks[n - 1];
    for (int i = n - 2; i >= 1; --i) {
      Film joined = chunks[i];
      joined.merge(tail);
      tail = std::move(joined);
    }
    Film grouped = chunks[0];
    if (n > 1) grouped.merge(tail);
    EXPECT_EQ(film_bytes(grouped), expected) << n << " sample chunks, grouped from the right";
  }
}

TEST_F(RendererApi, TileChunksMergeBitIdenticalToOneRender) {
  const std::string expected = film_bytes(reference_);
  for (int n : {1, 2, 3, 7}) {
    // Bands of rows, merged in reverse order; each film holds only its own window.
    std::vector<Film> tiles;
    for (int i = 0; i < n; ++i) {
      tiles.push_back(renderer_.make_film(row_chunk(renderer_.image_region(), i, n), 0));
      renderer_.render(tiles.back());
    }
    Film merged = renderer_.make_film();
    for (int i = n - 1; i >= 0; --i) merged.merge(tiles[static_cast<size_t>(i)]);
    EXPECT_EQ(film_bytes(merged), expected) << n << " row chunks";
  }
  // Irregular rectangles (not aligned to the 16-pixel tile grid) rendered into one film.
  Film film = renderer_.make_film();
  for (const PixelRegion& r :
       {PixelRegion{0, 0, 13, 7}, PixelRegion{13, 0, 40, 7}, PixelRegion{0, 7, 29, 24}, PixelRegion{29, 7, 40, 24}})
    renderer_.render(film, r, {0, kSpp});
  EXPECT_EQ(film_bytes(film), expected);
}

TEST_F(RendererApi, TilesTimesSampleChunksMergeBitIdentical) {
  // 3 row bands × 7 sample chunks, each its own film; merged band by band, then into the image.
  Film merged = renderer_.make_film();
  for (int t = 2; t >= 0; --t) {
    const PixelRegion band = row_chunk(renderer_.image_region(), t, 3);
    Film band_film = renderer_.make_film(band, 0);
    for (int i = 0; i < 7; ++i) {
      const SampleRange r = sample_chunk({0, kSpp}, i, 7);
      Film chunk = renderer_.make_film(band, r.first);
      renderer_.render(chunk, band, r);
      band_film.merge(chunk);
    }
    merged.merge(band_film);
  }
  EXPECT_EQ(film_bytes(merged), film_bytes(reference_));
}

TEST_F(RendererApi, SampleChunksSurviveACheckpointRoundTrip) {
  // What `--chunk i/N` then `sylva merge` does: chunk films go through files.
  const auto dir = std::filesystem::temp_directory_path();
  Film merged = renderer_.make_film();
  for (int i = 0; i < 3; ++i) {
    const SampleRange r = sample_chunk({0, kSpp}, i, 3);
    Film chunk = renderer_.make_film(renderer_.image_region(), r.first);
    renderer_.render(chunk, renderer_.image_region(), r);
    const auto file = dir / ("sylva_chunk_" + std::to_string(::getpid()) + "_" + std::to_string(i));
    chunk.save(file, "chunks");
    const Film back = Film::load(file, "chunks");
    std::filesystem::remove(file);
    EXPECT_EQ(film_bytes(back), film_bytes(chunk));
    merged.merge(back);
  }
  EXPECT_EQ(film_bytes(merged), film_bytes(reference_));
}

TEST_F(RendererApi, OutOfOrderMergesAndGapsAreRefused) {
  const SampleRange a = sample_chunk({0, kSpp}, 0, 3), b = sample_chunk({0, kSpp}, 1, 3),
                    c = sample_chunk({0, kSpp}, 2, 3);
  Film fa = renderer_.make_film(), fc = renderer_.make_film(renderer_.image_region(), c.first);
  renderer_.render(fa, renderer_.image_region(), a);
  renderer_.render(fc, renderer_.image_region(), c);
  const std::string before = film_bytes(fa);
  EXPECT_THROW(fa.merge(fc), Error);  // samples [b.first, c.first) are missing
  EXPECT_EQ(film_bytes(fa), before) << "a refused merge changes nothing";
  EXPECT_THROW(fa.merge(fa), Error);  // an overlap
  // Rendering a range that does not start where the film's pixels end is a gap too.
  EXPECT_THROW(renderer_.render(fa, renderer_.image_region(), c), Error);
  // A window outside the film's, and films of other images, are refused.
  Film tile = renderer_.make_film({0, 0, 8, 8}, 0);
  EXPECT_THROW(renderer_.render(tile, {0, 0, 9, 8}, {0, 1}), Error);
  EXPECT_THROW(tile.merge(fa), Error);
  EXPECT_THROW(fa.merge(Film(kWidth + 1, kHeight, fa.channels())), Error);
  EXPECT_THROW(renderer_.make_film({30, 0, 41, 8}, 0), Error);
  // Continuing a film's pixels with b, then c, completes it.
  Film fb = renderer_.make_film(renderer_.image_region(), b.first);
  renderer_.render(fb, renderer_.image_region(), b);
  fa.merge(fb);
  fa.merge(fc);
  EXPECT_EQ(film_bytes(fa), film_bytes(reference_));
}

TEST_F(RendererApi, RegionRenderTouchesOnlyItsPixelsAndItsImageIsACrop) {
  const PixelRegion region{7, 5, 30, 19};
  Film film = renderer_.make_film();
  const RenderStats stats = renderer_.render(film, region, {0, kSpp});
  EXPECT_EQ(stats.samples, uint64_t{kSpp} * region.pixel_count());
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) ASSERT_EQ(film.count(x, y), region.contains(x, y) ? uint32_t{kSpp} : 0u);
  // A film of just the region gives the region's crop of the full image, AOVs included.
  Film window = renderer_.make_film(region, 0);
  renderer_.render(window);
  const Image crop = renderer_.make_image(window);
  const Image full = renderer_.make_image(reference_);
  ASSERT_EQ(crop.width, region.width());
  ASSERT_EQ(crop.height, region.height());
  ASSERT_EQ(crop.channels, full.channels);
  for (int y = 0; y < crop.height; ++y)
    for (int x = 0; x < crop.width; ++x)
      for (int c = 0; c < static_cast<int>(crop.channels.size()); ++c)
        ASSERT_EQ(crop.at(x, y, c), full.at(x + region.x0, y + region.y0, c)) << crop.channels[c];
}

TEST_F(RendererApi, SampleRangeRendersOnlyThoseSamples) {
  Film film = renderer_.make_film();
  renderer_.render(film, renderer_.image_region(), {0, 5});
  EXPECT_EQ(film.total_samples(), uint64_t{5} * kWidth * kHeight);
  // Topping up to kSpp continues the same sequence: the single render's bits.
  const RenderStats more = renderer_.render(film, renderer_.image_region(), {5, kSpp});
  EXPECT_EQ(more.samples, uint64_t{kSpp - 5} * kWidth * kHeight);
  EXPECT_EQ(film_bytes(film), film_bytes(reference_));
  // A range the film already holds renders nothing.
  EXPECT_EQ(renderer_.render(film, renderer_.image_region(), {0, 3}).samples, 0u);
}

TEST_F(RendererApi, OneEmbreeSceneSharedByTwoRenderers) {
  // A renderer that builds its own BVHs and two that share this fixture's give the same bits;
  // the two sharing renderers differ in settings and render concurrently.
  Renderer own(scene_, test_settings(kWidth, kHeight, kSpp, kDepth));
  Film own_film = own.make_film();
  own.render(own_film);
  EXPECT_EQ(film_bytes(own_film), film_bytes(reference_));

  RenderSettings nir_only = test_settings(16, 10, 4, 3);
  nir_only.bands = {resolve_band("nir")};
  Renderer a(scene_, embree_, test_settings(kWidth, kHeight, kSpp, kDepth));
  Renderer b(scene_, embree_, nir_only);
  EXPECT_EQ(&a.embree(), &embree_);
  EXPECT_EQ(&b.embree(), &embree_);
  Film fa = a.make_film(), fb = b.make_film();
  std::thread ta([&] { a.render(fa); });
  std::thread tb([&] { b.render(fb); });
  ta.join();
  tb.join();
  EXPECT_EQ(film_bytes(fa), film_bytes(reference_));
  Renderer b_alone(scene_, nir_only);
  Film fb_alone = b_alone.make_film();
  b_alone.render(fb_alone);
  EXPECT_EQ(film_bytes(fb), film_bytes(fb_alone));
  EXPECT_EQ(b.make_image(fb).channels.size(), 1u + 1u + 1u + 11u);  // nir.Y, var, albedo, Z, N, P, four ids

  // An Embree scene of another scene is refused.
  const Scene other = small_forest_scene();
  EXPECT_THROW(Renderer(other, embree_, nir_only), Error);
}

// Distance from `p` to the polyline through `points`.
float distance_to_polyline(const Vec3& p, const Vec3* points, size_t n) {
  float best = glm::length(p - points[0]);
  for (size_t i = 0; i + 1 < n; ++i) {
    const Vec3 d = points[i + 1] - points[i];
    const float len2 = glm::dot(d, d);
    const float t = len2 > 0 ? std::clamp(glm::dot(p - points[i], d) / len2, 0.0f, 1.0f) : 0.0f;
    best = std::min(best, glm::length(p - (points[i] + t * d)));
  }
  return best;
}

TEST(LeafStem, AHitLeafNamesTheStemThatCarriesIt) {
  const WeberPennParams params = test::quaking_aspen();
  const TreeModel model = make_weber_penn_tree(params, 11);
  Scene scene;
  const uint32_t bark = scene.add_material("bark", make_diffuse("bark", DenseSpectrum::constant(0.3f)));
  const uint32_t leaf =
      scene.add_material("leaf", make_leaf("leaf", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.4f)));
  TreeMesh mesh = make_tree_mesh(model);
  Prototype tree{"aspen", std::move(mesh.stems), bark, std::move(mesh.leaves), leaf, {}, {}, {}, 0, {}, 0};
  const Vec3 offset(3, -2, 0);
  scene.instances.push_back({scene.add_prototype(std::move(tree)), glm::translate(Mat4(1.0f), offset), 7});
  Prototype cloud;
  cloud.leaves = make_leaf_cloud(LeafCloudParams{}, 2);
  cloud.leaf_material = leaf;
  scene.instances.push_back({scene.add_prototype(std::move(cloud)), glm::translate(Mat4(1.0f), Vec3(40, 0, 2)), 0});
  const EmbreeScene embree(scene);
  const Environment environment(scene.sun, scene.sky);
  const Integrator integrator(scene, embree, environment, IntegratorSettings{});

  Bounds3 box;
  for (const Vec3& p : model.sections.positions) box.extend(p);
  int leaf_hits = 0, stem_hits = 0;
  std::set<int32_t> stems_seen;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j) {
      const Vec3 target = offset + Vec3(box.lo.x + (box.hi.x - box.lo.x) * (i + 0.5f) / 60.0f, 0.0f,
                                        box.lo.z + (box.hi.z - box.lo.z) * (j + 0.5f) / 60.0f);
      const Vec3 origin = target - Vec3(0, 50, 0);
      const Ray ray{origin, Vec3(0, 1, 0)};
      RayHit hit;
      if (!embree.intersect(ray, &hit)) continue;
      const HitContext si = integrator.interaction(ray, hit);
      EXPECT_EQ(si.instance, 0u);
      EXPECT_EQ(si.prototype, 0u);
      EXPECT_EQ(si.primitive, hit.primitive);
      if (!si.leaf) {
        ++stem_hits;
        EXPECT_EQ(si.stem, -1);
        continue;
      }
      ++leaf_hits;
      // The primitive is the model's leaf of that index: the hit lies on that leaf's blade ...
      const size_t k = si.primitive;
      const Frame& f = model.leaves.frames[k];
      const Vec3 local = si.p - offset - model.leaves.positions[k];
      EXPECT_NEAR(glm::dot(local, f.y), 0.0f, 1e-3f);
      EXPECT_GE(glm::dot(local, f.z), -1e-3f);
      EXPECT_LE(glm::dot(local, f.z), model.leaves.length_m[k] + 1e-3f);
      // ... and the stem the hit names carries it: the petiole starts on that stem's axis.
      ASSERT_GE(si.stem, 0);
      ASSERT_LT(static_cast<size_t>(si.stem), model.stems.size());
      EXPECT_EQ(si.stem, model.leaves.stem[k]);
      const size_t s = static_cast<size_t>(si.stem);
      const float petiole = params.leaf_stem_len * model.leaves.length_m[k];
      EXPECT_LE(distance_to_polyline(model.leaves.positions[k], &model.sections.positions[model.stems.first_section[s]],
                                     model.stems.section_count[s]),
                petiole * 1.01f + 1e-4f)
          << "leaf " << k << " on stem " << s;
      stems_seen.insert(si.stem);
    }
  EXPECT_GT(leaf_hits, 100);
  EXPECT_GT(stem_hits, 0);
  EXPECT_GT(stems_seen.size(), 10u);

  // Leaves without a tree model (a leaf cloud) have no stem.
  int cloud_hits = 0;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      const Ray at_cloud{Vec3(39 + 0.2f * i, -20, 1 + 0.2f * j), Vec3(0, 1, 0)};
      RayHit hit;
      if (!embree.intersect(at_cloud, &hit)) continue;
      const HitContext si = integrator.interaction(at_cloud, hit);
      EXPECT_TRUE(si.leaf);
      EXPECT_EQ(si.instance, 1u);
      EXPECT_EQ(si.stem, -1);
      ++cloud_hits;
    }
  EXPECT_GT(cloud_hits, 10);
}

// Mesh triangles reach Embree paired into quads (render/embree_scene.cpp, MeshQuads): a hit still
// names the mesh's own triangle, with barycentrics on that triangle's corners. The mesh holds a fan
// pair (a, b, c), (a, c, d) over a non-planar square, which becomes one quad; a pair split along the
// other diagonal and a lone triangle, which stay triangles. Rays straight down at a grid of points:
// each hit names the triangle under the point, and its barycentrics give back the point.
TEST(MeshHits, PairedAndLoneTrianglesKeepTheirIndexAndBarycentrics) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0.1f}, {1, 1, 0.3f}, {0, 1, 0.05f},  // fan pair over [0,1]²
                    {2, 0, 0}, {3, 0, 0.2f}, {3, 1, 0},    {2, 1, 0.1f},   // pair split along 5–7
                    {4, 0, 0}, {5, 0, 0},    {4, 1, 0.2f}};                // a lone triangle
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 7}, {5, 6, 7}, {8, 9, 10}};
  Scene scene;
  const uint32_t m = scene.add_material("grey", make_diffuse("grey", DenseSpectrum::constant(0.5f)));
  Prototype proto;
  proto.name = "mesh";
  proto.triangles = mesh;
  proto.triangle_material = m;
  const Vec3 offset(10, -3, 1);
  scene.instances.push_back({scene.add_prototype(std::move(proto)), glm::translate(Mat4(1.0f), offset), 0});
  const EmbreeScene embree(scene);
  const Environment environment(scene.sun, scene.sky);
  const Integrator integrator(scene, embree, environment, IntegratorSettings{});

  // The triangle whose (x, y) projection holds (x, y), or −1.
  const auto triangle_under = [&](float x, float y) {
    for (size_t k = 0; k < mesh.triangles.size(); ++k) {
      const glm::uvec3 t = mesh.triangles[k];
      const Vec2 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
      const auto side = [](Vec2 p, Vec2 q, Vec2 r) { return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x); };
      const Vec2 p(x, y);
      const float s0 = side(a, b, p), s1 = side(b, c, p), s2 = side(c, a, p);
      if ((s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0)) return static_cast<int>(k);
    }
    return -1;
  };
  std::vector<int> hits_per_triangle(mesh.triangles.size(), 0);
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 20; ++j) {
      const float x = 5.0f * (i + 0.37f) / 100.0f, y = (j + 0.41f) / 20.0f;
      const int expected = triangle_under(x, y);
      const Ray ray{offset + Vec3(x, y, 5), Vec3(0, 0, -1)};
      RayHit hit;
      if (!embree.intersect(ray, &hit)) {
        EXPECT_EQ(expected, -1) << x << ", " << y;
        continue;
      }
      ASSERT_GE(expected, 0) << x << ", " << y;
      EXPECT_NE(hit.kind, PrimitiveKind::kLeafQuads);
      ASSERT_EQ(hit.primitive, static_cast<uint32_t>(expected)) << x << ", " << y;
      ++hits_per_triangle[expected];
      const glm::uvec3 t = mesh.triangles[hit.primitive];
      const Vec3 on_ray = ray.origin + hit.t * ray.direction - offset;
      const Vec3 from_barycentrics =
          (1.0f - hit.u - hit.v) * mesh.positions[t.x] + hit.u * mesh.positions[t.y] + hit.v * mesh.positions[t.z];
      EXPECT_LT(glm::length(from_barycentrics - on_ray), 1e-5f) << "triangle " << hit.primitive;
      EXPECT_LT(glm::length(integrator.interaction(ray, hit).p - offset - on_ray), 1e-5f);
    }
  for (size_t k = 0; k < mesh.triangles.size(); ++k) EXPECT_GT(hits_per_triangle[k], 50) << "triangle " << k;
}

}  // namespace
}  // namespace sylva
