#include "geometry/leaf_discs.h"

#include "core/error.h"
#include "core/input_file.h"

#include <fmt/core.h>

#include <array>
#include <charconv>
#include <cmath>
#include <sstream>

namespace sylva {

double LeafDiscs::area() const {
  double a = 0;
  for (const float r : radius) a += kPi * static_cast<double>(r) * r;
  return a;
}

namespace {

// Calls row(line_no, values) for each data row of a whitespace-separated table of `columns`
// numbers (`what` names them in messages); returns the number of the last line.
template <size_t N, class Row>
int read_rows(const std::filesystem::path& file, const char* what, const char* kind, const Row& row) {
  const std::string text = read_input_file(file, kMaxMeshFileBytes, kind);
  std::istringstream lines(text);
  std::string line;
  int line_no = 0;
  while (std::getline(lines, line)) {
    ++line_no;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::array<float, N> v{};
    size_t n = 0;
    const char* p = line.data();
    const char* end = line.data() + line.size();
    while (true) {
      while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
      if (p == end) break;
      if (n == N) throw ParseError(file, line_no, fmt::format("expected {} numbers ({}), found more", N, what));
      const auto [ptr, ec] = std::from_chars(p, end, v[n]);
      if (ec != std::errc() || (ptr < end && *ptr != ' ' && *ptr != '\t' && *ptr != '\r'))
        throw ParseError(file, line_no, fmt::format("expected a number in column {} ({})", n + 1, what));
      if (!std::isfinite(v[n])) throw ParseError(file, line_no, fmt::format("column {} is not finite", n + 1));
      ++n;
      p = ptr;
    }
    if (n < N) throw ParseError(file, line_no, fmt::format("expected {} numbers ({}), found {}", N, what, n));
    row(line_no, v);
  }
  return line_no;
}

}  // namespace

std::vector<Vec3> read_points(const std::filesystem::path& file) {
  std::vector<Vec3> out;
  const int last = read_rows<3>(file, "x y z", "point file",
                                [&](int, const std::array<float, 3>& v) { out.emplace_back(v[0], v[1], v[2]); });
  if (out.empty()) throw ParseError(file, last, "the file holds no points");
  return out;
}

LeafDiscs read_leaf_discs(const std::filesystem::path& file) {
  LeafDiscs out;
  const int last = read_rows<7>(file, "radius cx cy cz nx ny nz", "leaf file", [&](int line_no, const auto& v) {
    if (!(v[0] > 0)) throw ParseError(file, line_no, "the disc radius must be positive");
    const Vec3 normal(v[4], v[5], v[6]);
    const float len = glm::length(normal);
    if (!(len > 0)) throw ParseError(file, line_no, "the disc normal must not be zero");
    out.add(Vec3(v[1], v[2], v[3]), v[0], normal / len);
  });
  if (out.size() == 0) throw ParseError(file, last, "the leaf file holds no leaves");
  return out;
}

LeafAngles parse_leaf_angles(const std::string& name) {
  if (name == "uniform" || name == "spherical") return LeafAngles::spherical;
  if (name == "planophile") return LeafAngles::planophile;
  if (name == "erectophile") return LeafAngles::erectophile;
  throw Error("leaf angles must be \"uniform\" (= \"spherical\"), \"planophile\" or \"erectophile\", not \"" + name +
              "\"");
}

Vec3 sample_leaf_normal(LeafAngles angles, Pcg32& rng) {
  float cos_theta = 0;
  if (angles == LeafAngles::spherical) {
    cos_theta = rng.uniform();  // g(θ) = sin θ on [0, π/2]: cos θ uniform
  } else {
    // de Wit's densities are (2/π)(1 ± cos 2θ) ≤ 4/π: accept a uniform θ with probability (1 ± cos 2θ)/2.
    const float sign = angles == LeafAngles::planophile ? 1.0f : -1.0f;
    while (true) {
      const float theta = 0.5f * kPi * rng.uniform();
      if (rng.uniform() < 0.5f * (1.0f + sign * std::cos(2.0f * theta))) {
        cos_theta = std::cos(theta);
        break;
      }
    }
  }
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  const float phi = 2.0f * kPi * rng.uniform();
  return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

namespace {

size_t disc_count(double leaf_area, float radius) {
  const double n = std::round(leaf_area / (kPi * static_cast<double>(radius) * radius));
  if (!(n >= 1) || n > 5e7)
    throw Error(fmt::format("a canopy of {:g} m² of leaves in discs of radius {:g} m needs {:g} discs (1 to 5e7)",
                            leaf_area, radius, n));
  return static_cast<size_t>(n);
}

}  // namespace

LeafDiscs make_homogeneous_layer(Vec2 lo, Vec2 hi, float height, float lai, float radius, LeafAngles angles,
                                 uint64_t seed) {
  if (!(hi.x > lo.x && hi.y > lo.y)) throw Error("the canopy's rectangle is empty");
  if (!(height > 2 * radius)) throw Error("the canopy height must exceed the disc diameter");
  const size_t n = disc_count(static_cast<double>(lai) * (hi.x - lo.x) * (hi.y - lo.y), radius);
  Pcg32 rng(seed, 0x6c65616664697363ull);
  LeafDiscs out;
  for (size_t i = 0; i < n; ++i) {
    const Vec3 u = uniform3(rng);
    const Vec3 c(lo.x + (hi.x - lo.x) * u.x, lo.y + (hi.y - lo.y) * u.y, radius + (height - 2 * radius) * u.z);
    out.add(c, radius, sample_leaf_normal(angles, rng));
  }
  return out;
}

LeafDiscs make_leaf_sphere(float sphere_radius, float lai, float radius, LeafAngles angles, uint64_t seed) {
  if (!(sphere_radius > radius)) throw Error("the sphere radius must exceed the disc radius");
  // Centres fill the whole sphere, as in RAMI's HET01 file (its centres reach 9.9999 m of 10 m):
  // keeping discs inside a sphere of R − r would shrink its cross-section by 2 % at the same leaf
  // area and lower the BRF by about as much.
  const size_t n = disc_count(static_cast<double>(lai) * kPi * sphere_radius * sphere_radius, radius);
  Pcg32 rng(seed, 0x7370686572656c66ull);
  LeafDiscs out;
  for (size_t i = 0; i < n; ++i) {
    Vec3 c;
    do {
      c = symmetric3(rng);
    } while (glm::dot(c, c) > 1.0f);
    out.add(sphere_radius * c, radius, sample_leaf_normal(angles, rng));
  }
  return out;
}

}  // namespace sylva
