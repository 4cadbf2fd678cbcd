#pragma once
// Leaves as exact discs (the RAMI benchmark's abstract canopies): a centre, a radius and a unit
// normal per leaf, intersected analytically by the renderer (no polygon changes the leaf area).
// Read from a RAMI leaf file, or generated: a homogeneous layer of discs, or a sphere filled with
// discs (RAMI-3 HET01). Units are metres; Z is up.

#include "core/math.h"
#include "core/rng.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

// One entry per leaf. `normal` is unit length; a disc has no preferred side, but the normal is the
// side the leaf material calls its front (upper) face.
struct LeafDiscs {
  std::vector<Vec3> centre;
  std::vector<float> radius;
  std::vector<Vec3> normal;

  size_t size() const { return centre.size(); }
  void add(const Vec3& c, float r, const Vec3& n) {
    centre.push_back(c);
    radius.push_back(r);
    normal.push_back(n);
  }
  // One-sided leaf area Σ π r², m².
  double area() const;
};

// Reads a RAMI leaf file: one leaf per row, `radius cx cy cz nx ny nz`, whitespace separated;
// blank lines and lines starting with '#' are skipped. Normals are normalised. Throws
// sylva::ParseError ("file:line: ...") for a short row, a bad number, a radius ≤ 0, a zero normal.
LeafDiscs read_leaf_discs(const std::filesystem::path& file);

// Reads points, one per row `x y z` (whitespace separated; blank lines and '#' lines skipped), e.g.
// the RAMI-3 HET01 sphere centres. Throws sylva::ParseError ("file:line: ...").
std::vector<Vec3> read_points(const std::filesystem::path& file);

// Leaf-angle distributions (de Wit 1965; the RAMI abstract canopies): the density of the leaf
// inclination θ_L (angle between the leaf normal and the zenith), azimuth uniform.
//   spherical (= RAMI "uniform"): normals uniform over the sphere, g(θ_L) = sin θ_L, G = 0.5
//   planophile:  g(θ_L) = (2/π)(1 + cos 2θ_L)     erectophile: g(θ_L) = (2/π)(1 − cos 2θ_L)
enum class LeafAngles { spherical, planophile, erectophile };
// "uniform" and "spherical" are both `spherical`; throws sylva::Error for any other name.
LeafAngles parse_leaf_angles(const std::string& name);
// A unit leaf normal (upper hemisphere) drawn from the distribution; planophile and erectophile
// inclinations by rejection from a uniform θ_L (acceptance 1/2).
Vec3 sample_leaf_normal(LeafAngles angles, Pcg32& rng);

// A homogeneous layer: discs of radius `radius` with centres uniform over the rectangle
// [lo, hi] (x, y) and over heights [radius, height − radius], so every disc lies inside the layer
// whatever its tilt; as many as give the leaf area index `lai` over the rectangle
// (round(lai · area / (π r²))). Deterministic for a seed.
LeafDiscs make_homogeneous_layer(Vec2 lo, Vec2 hi, float height, float lai, float radius, LeafAngles angles,
                                 uint64_t seed);

// A sphere of radius `sphere_radius` centred on the origin filled with discs whose centres are
// uniform in it (as in RAMI's HET01 file; a disc near the surface may reach out by its radius),
// as many as give
// the sphere's leaf area index `lai` = leaf area / (π R²) (RAMI-3 HET01: R = 10 m, LAI 5, r = 0.1 m:
// 50,000 discs). Deterministic for a seed.
LeafDiscs make_leaf_sphere(float sphere_radius, float lai, float radius, LeafAngles angles, uint64_t seed);

}  // namespace sylva
