#pragma once
// Small scenes and settings shared by the render tests (transport, renderer API, session).

#include "geometry/primitives.h"
#include "render/renderer.h"

#include <glm/gtc/matrix_transform.hpp>

#include <unistd.h>

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

// Ground, sun and sky, and two instances of one alpha-cut leaf cloud (object id 1).
inline Scene small_forest_scene() {
  Scene s;
  s.camera.position = {0, -5, 1.5f};
  s.camera.target = {0, 0, 1.0f};
  s.sun.elevation_deg = 35;
  s.sun.azimuth_deg = 160;
  const uint32_t soil = s.add_material("soil", make_diffuse("soil", DenseSpectrum::constant(0.2f)));
  const uint32_t leaf =
      s.add_material("leaf", make_leaf("leaf", DenseSpectrum::constant(0.3f), DenseSpectrum::constant(0.4f)));
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

}  // namespace sylva::test
