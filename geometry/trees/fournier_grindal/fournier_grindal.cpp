#include "geometry/trees/fournier_grindal/fournier_grindal.h"

#include "core/error.h"
#include "core/rng.h"

#include <fmt/core.h>

#include <cmath>
#include <numbers>

namespace sylva {

namespace {

constexpr float kDeg = std::numbers::pi_v<float> / 180.0f;

// gauss() of §2.1: a standard normal deviate (Box–Muller).
float gauss(Pcg32& rng) {
  const double u1 = 1.0 - rng.uniform_double(), u2 = rng.uniform_double();
  return static_cast<float>(std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2));
}

// §2.1 pruning: "the normal is retained if and only if ax ≥ 0 AND by ≥ 0 AND cz ≥ 0" for normal
// (a, b, c) with origin (x, y, z), the crown centre being the origin.
bool outward(const Vec3& origin, const Vec3& direction) {
  return direction.x * origin.x >= 0.0f && direction.y * origin.y >= 0.0f && direction.z * origin.z >= 0.0f;
}

HalfSpace plane_of(const FgNormal& n) {
  return HalfSpace{n.direction, glm::dot(n.direction, n.origin + n.length * n.direction)};
}

// §5: "the trunk can be described as a hexagonal cylinder, or cone": six side planes whose distance
// from the axis falls linearly from r0 at z = 0 to r1 at z = height, plus the bottom and top caps.
ConvexPolytope hexagonal_trunk(float r0, float r1, float height) {
  ConvexPolytope planes;
  const float k = (r0 - r1) / height;
  for (int i = 0; i < 6; ++i) {
    const float a = static_cast<float>(i) * std::numbers::pi_v<float> / 3.0f;
    const Vec3 n(std::cos(a), std::sin(a), k);
    const float l = glm::length(n);
    planes.push_back(HalfSpace{n / l, r0 / l});
  }
  planes.push_back(HalfSpace{Vec3(0, 0, -1), 0.0f});
  planes.push_back(HalfSpace{Vec3(0, 0, 1), height});
  return planes;
}

}  // namespace

FgCrown make_fournier_grindal_crown(const FournierGrindalParams& p, uint64_t seed) {
  Pcg32 rng(hash_ids(seed, 0x46475f63726f776eull));
  FgCrown crown;
  std::vector<int> current;
  for (const Vec3& v : p.normals) {
    const float l = glm::length(v);
    if (!(l > 0.0f)) throw Error("fournier-grindal: an initial normal has zero length");
    crown.history.push_back(FgNormal{Vec3(0.0f), v / l, l, 0, -1, true});
    current.push_back(static_cast<int>(crown.history.size() - 1));
  }
  float mu_alpha = p.mu_alpha_deg * kDeg, sigma_alpha = p.sigma_alpha_deg * kDeg;
  for (int g = 1; g <= p.generations; ++g) {
    std::vector<int> next;
    for (const int index : current) {
      const FgNormal n1 = crown.history[size_t(index)];
      // Step 1: B lies |BC| = l1(μ_B + gauss σ_B) down the normal from its tip C.
      const float bc = n1.length * (p.mu_b + gauss(rng) * p.sigma_b);
      const Vec3 tip = n1.origin + n1.length * n1.direction;
      const Vec3 b = tip - bc * n1.direction;
      // Step 2: the two angles; the split plane (Figure 1 is 2-D) turns about N1 by a uniform
      // azimuth, N2 and N3 lying on either side of N1 in it.
      const float a1 = mu_alpha + gauss(rng) * sigma_alpha;
      const float a2 = mu_alpha + gauss(rng) * sigma_alpha;
      const float phi = 2.0f * std::numbers::pi_v<float> * rng.uniform();
      const Frame f = Frame::from_z(n1.direction);
      const Vec3 side = std::cos(phi) * f.x + std::sin(phi) * f.y;
      // Step 3: lengths that put the new tips on P1 on average.
      const float l2 = bc / std::cos(a1) + gauss(rng) * p.sigma_l * n1.length;
      const float l3 = bc / std::cos(a2) + gauss(rng) * p.sigma_l * n1.length;
      int kept = 0;
      for (const auto& [a, l, s] : {std::tuple{a1, l2, 1.0f}, std::tuple{a2, l3, -1.0f}}) {
        const Vec3 dir = glm::normalize(std::cos(a) * n1.direction + s * std::sin(a) * side);
        FgNormal child{b, dir, l, g, index, outward(b, dir) && l > 0.0f};
        crown.history.push_back(child);
        if (child.kept) {
          next.push_back(static_cast<int>(crown.history.size() - 1));
          ++kept;
        }
      }
      // Both children rejected: the parent plane stays, so the crown keeps its extent there.
      if (kept == 0) next.push_back(index);
    }
    current = std::move(next);
    // Step 4: smaller angles each generation.
    mu_alpha *= p.ratio;
    sigma_alpha *= p.ratio;
  }
  for (const int index : current) crown.planes.push_back(plane_of(crown.history[size_t(index)]));
  return crown;
}

std::vector<Vec3> fournier_grindal_bark_palette(const FournierGrindalParams& p, uint64_t seed) {
  Pcg32 rng(hash_ids(seed, 0x46475f6261726bull));
  std::vector<Vec3> out;
  for (int i = 0; i < kFournierGrindalBarkColours; ++i) {
    const float r = rng.uniform(), g = rng.uniform(), b = rng.uniform();
    out.push_back(p.bark_rgb + Vec3(r, g, b) * p.bark_range_rgb);
  }
  return out;
}

TreeModel make_fournier_grindal_tree(const FournierGrindalParams& p, uint64_t seed) {
  const FgCrown crown = make_fournier_grindal_crown(p, seed);
  const PolytopeFaces faces = polytope_faces(crown.planes, kSolidExtentM);
  if (faces.polygons.empty()) throw Error("fournier-grindal: the crown's half-spaces have an empty intersection");
  if (!faces.bounded) throw Error("fournier-grindal: the initial normals do not enclose the crown centre");
  float z_lo = 0.0f;
  for (const auto& poly : faces.polygons)
    for (const Vec3& v : poly) z_lo = std::min(z_lo, v.z);
  // The crown's lowest point at crown_base_m; the trunk runs halfway up to the crown centre (§5:
  // the trunk is placed under "the centre of the tree").
  const float lift = p.crown_base_m - z_lo;
  TreeModel model;
  HalfSpaceSolid c;
  c.planes = crown.planes;
  for (HalfSpace& hs : c.planes) hs.offset += hs.normal.z * lift;
  c.displacement_m = p.displacement_m;
  c.displacement = p.fbm;
  c.displacement.seed = hash_ids(seed, 1);
  c.colouring.kind = SolidColouring::Kind::Fbm;
  c.colouring.fbm = p.fbm;
  c.colouring.fbm.seed = hash_ids(seed, 2);
  c.material_slot = 1;
  c.leaf_area_density = p.leaf_area_density;
  finish_solid(c);
  HalfSpaceSolid t;
  t.planes = hexagonal_trunk(p.trunk_radius_m, p.trunk_top_radius_m, p.crown_base_m - 0.5f * z_lo);
  t.colouring.kind = SolidColouring::Kind::Cells;
  t.colouring.cell_m = p.bark_cell_m;
  t.colouring.seed = hash_ids(seed, 3);
  t.material_slot = 0;
  finish_solid(t);
  model.solids = {std::move(t), std::move(c)};
  return model;
}

TreeModel make_tree(const FournierGrindalParams& params, uint64_t seed, const TreeOptions&) {
  return make_fournier_grindal_tree(params, seed);
}

FournierGrindalParams FournierGrindalParams::create(const Params& params, std::vector<std::string>&) {
  FournierGrindalParams p;
  const auto triples = [&](std::string_view key, float lo, float hi) {
    const std::vector<double> v = params.numbers(key);
    if (v.empty() || v.size() % 3 != 0)
      params.fail(key, fmt::format("'{}' must list x, y, z triples (a multiple of 3 numbers)", key));
    std::vector<Vec3> out;
    for (size_t i = 0; i < v.size(); i += 3) {
      for (size_t k = i; k < i + 3; ++k)
        if (!(v[k] >= lo && v[k] <= hi)) params.fail(key, fmt::format("'{}' values must be in [{}, {}]", key, lo, hi));
      out.emplace_back(v[i], v[i + 1], v[i + 2]);
    }
    return out;
  };
  if (!params.has("normals"))
    params.fail("model", "a fournier-grindal species needs 'normals' (x, y, z triples, metres)");
  p.normals = triples("normals", -1e3f, 1e3f);
  if (p.normals.size() < 3) params.fail("normals", "'normals' needs at least 3 vectors (§2.1 suggests 3 to 6)");
  for (const Vec3& n : p.normals)
    if (glm::length(n) <= 0.0f) params.fail("normals", "every initial normal needs a non-zero length");
  p.generations = static_cast<int>(params.integer("generations", p.generations, 0, 8));
  p.mu_b = params.real("mu_b", p.mu_b, 0.0, 1.0);
  p.sigma_b = params.real("sigma_b", p.sigma_b, 0.0, 1.0);
  p.mu_alpha_deg = params.real("mu_alpha", p.mu_alpha_deg, 0.0, 80.0);
  p.sigma_alpha_deg = params.real("sigma_alpha", p.sigma_alpha_deg, 0.0, 45.0);
  p.sigma_l = params.real("sigma_l", p.sigma_l, 0.0, 1.0);
  p.ratio = params.real("ratio", p.ratio, 0.0, 1.0);
  p.displacement_m = params.real("displacement", p.displacement_m, 0.0, 100.0);
  p.fbm.hurst = params.real("hurst", p.fbm.hurst, 0.05, 1.0);
  p.fbm.lacunarity = params.real("lacunarity", p.fbm.lacunarity, 1.1, 8.0);
  p.fbm.octaves = static_cast<int>(params.integer("octaves", p.fbm.octaves, 1, 12));
  p.fbm.wavelength_m = params.real("wavelength", p.fbm.wavelength_m, 1e-3, 1e3);
  const std::string optics = params.string("optics", "surface");
  if (optics == "turbid") {
    p.leaf_area_density = params.real("lad", 1.0, 1e-4, 1e3);
  } else if (optics != "surface") {
    params.fail("optics", "optics must be \"surface\" (opaque, the paper's) or \"turbid\" (a leaf medium)");
  }
  if (params.has("crown_colours")) p.crown_rgb = triples("crown_colours", 0.0f, 1.0f);
  p.crown_base_m = params.real("crown_base", p.crown_base_m, 0.0, 1e3);
  p.trunk_radius_m = params.real("trunk_radius", p.trunk_radius_m, 1e-3, 100.0);
  p.trunk_top_radius_m = params.real("trunk_top_radius", p.trunk_top_radius_m, 1e-3, 100.0);
  p.bark_rgb = params.vec3("bark_colour", p.bark_rgb);
  p.bark_range_rgb = params.vec3("bark_range", p.bark_range_rgb);
  for (int i = 0; i < 3; ++i) {
    if (p.bark_rgb[i] < 0.0f || p.bark_rgb[i] > 1.0f) params.fail("bark_colour", "'bark_colour' must be in [0, 1]");
    if (p.bark_range_rgb[i] < 0.0f || p.bark_rgb[i] + p.bark_range_rgb[i] > 1.0f)
      params.fail("bark_range", "'bark_range' must be ≥ 0 with bark_colour + bark_range ≤ 1");
  }
  p.bark_cell_m = params.real("bark_cell", p.bark_cell_m, 1e-4, 10.0);
  params.check_unused();
  return p;
}

}  // namespace sylva
