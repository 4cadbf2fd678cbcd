#pragma once
// Small scenes and settings shared by the render tests (transport, renderer API, session).

#include "geometry/grass.h"
#include "geometry/primitives.h"
#include "render/embree_scene.h"
#include "render/renderer.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sylva::test {

inline std::vector<Band> test_bands() { return {resolve_band("rgb"), resolve_band("nir")}; }

inline RenderSettings test_settings(int w, int h, int spp, int max_depth = 64) {
  RenderSettings settings;
  settings.width = w;
  settings.height = h;
  settings.spp = spp;
  settings.bands = test_bands();
  settings.progress = false;
  settings.integrator.max_depth = max_depth;
  return settings;
}

// A unit-radius cloud of `count` alpha-cut oval leaves (15 × 10 cm) of material `leaf`.
inline Prototype leaf_cloud_prototype(uint32_t leaf, int count, uint64_t seed) {
  Prototype p;
  LeafCloudParams lc;
  lc.radii = Vec3(1.0f);
  lc.count = count;
  lc.leaf_length_m = 0.15f;
  lc.leaf_width_m = 0.1f;
  p.leaves = make_leaf_cloud(lc, seed);
  p.leaf_material = leaf;
  return p;
}

// A scene without geometry seen from `position` towards `target` under the sun at `elevation_deg`
// and `azimuth_deg`, with grey soil (ρ 0.2) and leaf (ρ 0.3, τ 0.4) materials, 0 and 1.
inline Scene grey_scene(Vec3 position, Vec3 target, float elevation_deg, float azimuth_deg) {
  Scene s;
  s.camera.position = position;
  s.camera.target = target;
  s.sun.elevation_deg = elevation_deg;
  s.sun.azimuth_deg = azimuth_deg;
  s.add_material("soil", make_diffuse("soil", DenseSpectrum::constant(0.2f)));
  s.add_material("leaf", make_leaf("leaf", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.4f)));
  return s;
}
constexpr uint32_t kGreySoil = 0, kGreyLeaf = 1;

// Ground, sun and sky, and two instances of one alpha-cut leaf cloud (object id 1).
inline Scene small_forest_scene() {
  Scene s = grey_scene({0, -5, 1.5f}, {0, 0, 1.0f}, 35, 160);
  const uint32_t soil = kGreySoil, leaf = kGreyLeaf;
  s.instances.push_back(
      {s.add_prototype(Prototype{"ground", make_plane(100, 100), soil, {}, 0, {}, {}, {}, 0, {}, 0}), Mat4(1.0f), 0});
  Prototype crown;
  crown.leaves = make_leaf_cloud(LeafCloudParams{}, 5);
  crown.leaf_material = leaf;
  const uint32_t c = s.add_prototype(crown);
  s.instances.push_back({c, glm::translate(Mat4(1.0f), Vec3(-1, 0, 1.8f)), 1});
  s.instances.push_back({c, glm::translate(Mat4(1.0f), Vec3(1.5f, 2, 2.0f)), 1});
  return s;
}

inline bool same_bits(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.channels == b.channels && a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

// A film's complete state as bytes (its checkpoint file): equal iff window, first sample, counts,
// sums, sums of squares and kept samples are bit-identical.
inline std::string film_bytes(const Film& film) {
  const auto file = std::filesystem::temp_directory_path() / ("sylva_film_bytes_" + std::to_string(::getpid()));
  film.save(file, "bytes");
  std::stringstream s;
  s << std::ifstream(file, std::ios::binary).rdbuf();
  std::filesystem::remove(file);
  return s.str();
}

// Instance levels (render/embree_scene.h): the same scenes and comparisons for each.

inline Scene with_level(Scene s, InstanceLevel level) {
  s.instance_level = level;
  return s;
}

// A ground, then a 5 x 4 stand of three kinds of prototypes — alpha-cut leaf clouds, boxes, grass
// patches — each copy turned, scaled non-uniformly (0.6–1.8) and labelled with its own object,
// class and variant ids; a leaf cloud hangs over every box so shadows cross prototypes.
inline Scene stand_scene() {
  Scene s = grey_scene({0, -6.5f, 2.5f}, {0, 1.5f, 1.0f}, 40, 150);
  const uint32_t soil = kGreySoil, leaf = kGreyLeaf;
  const uint32_t bark = s.add_material("bark", make_diffuse("bark", DenseSpectrum::constant(0.35f)));
  Prototype ground;
  ground.triangles = make_plane(100, 100);
  ground.triangle_material = soil;
  s.instances.push_back({s.add_prototype(std::move(ground)), Mat4(1.0f), 0, kClassTerrain, 0});
  const uint32_t cloud = s.add_prototype(leaf_cloud_prototype(leaf, 400, 7));
  Prototype box;
  box.triangles = make_box(Vec3(0.6f, 0.4f, 1.2f));
  box.triangle_material = bark;
  const uint32_t trunk = s.add_prototype(std::move(box));
  Prototype grass;
  GrassParams gp;
  gp.patch_size_m = 1.5f;
  gp.density_per_m2 = 300.0f;
  grass.curves = make_grass_patch(gp, 3);
  grass.curve_material = leaf;
  const uint32_t patch = s.add_prototype(std::move(grass));
  uint32_t object = 1;
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 5; ++col) {
      const float x = -4.0f + 2.0f * static_cast<float>(col) + 0.3f * static_cast<float>(row % 2);
      const float y = -1.0f + 2.2f * static_cast<float>(row);
      const float turn = 0.7f * static_cast<float>(row * 5 + col);
      const Vec3 scale(0.6f + 0.06f * static_cast<float>(col * 4 + row), 0.8f + 0.1f * static_cast<float>(row),
                       1.0f + 0.2f * static_cast<float>(col % 3));
      const Mat4 placed =
          glm::scale(glm::rotate(glm::translate(Mat4(1.0f), Vec3(x, y, 0.0f)), turn, Vec3(0, 0, 1)), scale);
      const uint32_t kind = static_cast<uint32_t>(row * 5 + col) % 3;
      if (kind == 0) {
        s.instances.push_back({trunk, placed, object++, kFirstNamedClass, 1});
        s.instances.push_back({cloud, glm::translate(placed, Vec3(0, 0, 1.6f)), object++, kFirstNamedClass, 2});
      } else if (kind == 1) {
        s.instances.push_back({cloud, glm::translate(placed, Vec3(0, 0, 1.0f)), object++, kFirstNamedClass + 1, 3});
      } else {
        s.instances.push_back({patch, placed, object++, kClassGrass, 0});
      }
    }
  return s;
}

inline Image render_with(const Scene& scene, int w, int h, int spp, uint64_t seed, int threads = 0,
                         const TransportFaults& faults = {}) {
  RenderSettings settings = test_settings(w, h, spp, 16);
  settings.seed = seed;
  settings.threads = threads;
  const EmbreeScene embree(scene, faults);
  Renderer r(scene, embree, settings, faults);
  Film film = r.make_film();
  r.render(film);
  return r.make_image(film);
}

struct Agreement {
  double worst_mean_z = 0;   // the largest |z| of a channel's image-mean difference
  int rejecting_pixels = 0;  // pixel-channels with |z| above the Sidak threshold
  int pixel_channels = 0;
};

// Two independent renders (different seeds) of the same scene: per channel the z-score of the
// difference of the image means, and per pixel-channel the z-score with the pooled variance of both
// means (docs/compare.md, as the golden checks).
inline Agreement agreement(const Image& a, const Image& b, double pixel_z) {
  Agreement out;
  for (const char* channel : {"R", "G", "B", "nir.Y"}) {
    const int c = a.find_channel(channel), v = a.find_channel(std::string("var.") + channel);
    EXPECT_GE(c, 0);
    EXPECT_GE(v, 0);
    double sum = 0, var = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        const double d = static_cast<double>(a.at(x, y, c)) - b.at(x, y, c);
        const double pooled = static_cast<double>(a.at(x, y, v)) + b.at(x, y, v);
        sum += d;
        var += pooled;
        ++out.pixel_channels;
        if (pooled > 0 ? std::abs(d) > pixel_z * std::sqrt(pooled) : d != 0) ++out.rejecting_pixels;
      }
    out.worst_mean_z = std::max(out.worst_mean_z, var > 0 ? std::abs(sum) / std::sqrt(var) : 0.0);
  }
  return out;
}

// Pixels whose first-hit label `channel` differs.
inline int label_mismatches(const Image& a, const Image& b, const char* channel) {
  const int c = a.find_channel(channel);
  EXPECT_GE(c, 0);
  int n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) n += a.at(x, y, c) != b.at(x, y, c);
  return n;
}

}  // namespace sylva::test
