#include "geometry/trees/hart_baker/hart_baker.h"

#include "core/error.h"
#include "core/hash.h"
#include "core/rng.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace sylva {

namespace {

constexpr double kPiD = 3.14159265358979323846;

DVec3 to_d(const Vec3& v) { return DVec3(v); }

// Horizontal part of a vector (Z up).
DVec3 horizontal(const DVec3& v) { return DVec3(v.x, v.y, 0.0); }

// Radius of limb i at distance s from its base (linear taper of the truncated cone).
float radius_at(const HartBakerTree& tree, const HartBakerParams& p, size_t i, float s) {
  const float R = tree.radius_m[i];
  const float r = tree.tip_radius(i, p);
  const float l = std::max(tree.length_m[i], 1e-6f);
  return R + (r - R) * std::clamp(s / l, 0.0f, 1.0f);
}

// Leaf k of limb i sits at arc (k + ½)·spacing; it exists where the limb is thinner than the
// threshold. Returns the number of leaf slots along the limb (some may be too thick).
int leaf_slots(const HartBakerTree& tree, const HartBakerParams& p, size_t i) {
  if (p.leaf_spacing_m <= 0.0f) return 0;
  return static_cast<int>(std::floor(tree.length_m[i] / p.leaf_spacing_m + 0.5f));
}

bool has_leaf(const HartBakerTree& tree, const HartBakerParams& p, size_t i, int k) {
  const float s = (static_cast<float>(k) + 0.5f) * p.leaf_spacing_m;
  return s <= tree.length_m[i] && radius_at(tree, p, i, s) < p.leaf_radius_m;
}

double leaf_area(const HartBakerTree& tree, const HartBakerParams& p, size_t i) {
  int n = 0;
  const int slots = leaf_slots(tree, p, i);
  for (int k = 0; k < slots; ++k) n += has_leaf(tree, p, i, k) ? 1 : 0;
  return n * static_cast<double>(p.leaf_length_m) * p.leaf_width_m;
}

// Direction at azimuth `phi` around `axis`, tilted `theta` from it.
Vec3 turn_from(const Vec3& axis, float theta, float phi) {
  const Frame f = Frame::from_z(axis);
  return glm::normalize(std::cos(theta) * axis + std::sin(theta) * (std::cos(phi) * f.x + std::sin(phi) * f.y));
}

void add_limb(HartBakerTree& t, int32_t parent, uint8_t order, const Vec3& base, const Vec3& dir, float length,
              float radius) {
  t.parent.push_back(parent);
  t.order.push_back(order);
  t.alive.push_back(1);
  t.born.push_back(t.year);
  t.base.push_back(base);
  t.direction.push_back(dir);
  t.length_m.push_back(length);
  t.radius_m.push_back(radius);
  t.apex.push_back(-1);
  t.lit.push_back(parent >= 0 ? t.lit[static_cast<size_t>(parent)] : 1.0f);
  t.ring_radius_m.push_back({});
  t.ring_length_m.push_back({});
  t.ring_offset_m.push_back({});
  t.reaction_m.push_back(Vec3(0.0f));
}

void kill_subtree(HartBakerTree& t, const std::vector<std::vector<int32_t>>& children, int32_t id) {
  std::vector<int32_t> stack{id};
  while (!stack.empty()) {
    const int32_t i = stack.back();
    stack.pop_back();
    t.alive[static_cast<size_t>(i)] = 0;
    for (const int32_t c : children[static_cast<size_t>(i)]) stack.push_back(c);
  }
}

}  // namespace

std::vector<std::vector<int32_t>> HartBakerTree::children() const {
  std::vector<std::vector<int32_t>> out(size());
  for (size_t i = 1; i < size(); ++i) out[static_cast<size_t>(parent[i])].push_back(static_cast<int32_t>(i));
  return out;
}

// Eq. 9: v = π l (R³ − r³) / (3 (R − r)) = π l (R² + R r + r²)/3.
double frustum_volume(double l, double R, double r) { return kPiD * l * (R * R + R * r + r * r) / 3.0; }

// Eq. 11: x̄ = l (R⁴ − r³(4R − 3r)) / (4 (R − r)(R³ − r³)). Dividing numerator and denominator by
// (R − r)² gives l (R² + 2 R r + 3 r²) / (4 (R² + R r + r²)), which is finite at R = r (l/2) and
// gives l/4 for a cone (r = 0).
double frustum_centroid(double l, double R, double r) {
  const double den = 4.0 * (R * R + R * r + r * r);
  if (den <= 0.0) return 0.5 * l;
  return l * (R * R + 2.0 * R * r + 3.0 * r * r) / den;
}

// Eq. 8: supports(R, d) = d·v(R, 0, H) = d π R² H / 3, so k = π H / 3 (π·100 ft for H = 300 ft).
double supports(double R, double d, double max_height_m) { return (kPiD * max_height_m / 3.0) * d * R * R; }

// Eq. 7.
double needs_to_support(double m, double d, double max_height_m) {
  return std::sqrt(std::max(0.0, m) / ((kPiD * max_height_m / 3.0) * d));
}

// Eq. 21 generalised to a truncated cone with r = tip_ratio·R: m = d π l R² (1 + τ + τ²)/3.
double length_for_mass(double m, double R, double tip_ratio, double d) {
  const double per_length = d * kPiD * R * R * (1.0 + tip_ratio + tip_ratio * tip_ratio) / 3.0;
  return per_length > 0.0 ? m / per_length : 0.0;
}

LimbSums compute_limb_sums(const HartBakerTree& tree, const HartBakerParams& params,
                           const std::vector<float>& light_m2) {
  const size_t n = tree.size();
  if (!light_m2.empty() && light_m2.size() != n)
    throw Error(fmt::format("Hart-Baker growth: {} light values for {} limbs", light_m2.size(), n));
  LimbSums s;
  s.m.assign(n, 0.0);
  s.M.assign(n, 0.0);
  s.x.assign(n, DVec3(0.0));
  s.X.assign(n, DVec3(0.0));
  s.o.assign(n, 0.0);
  s.p.assign(n, 0.0);
  s.P.assign(n, 0.0);
  s.g.assign(n, 0.0);
  s.G.assign(n, 0.0);
  s.leaf_area_m2.assign(n, 0.0);
  const double d = params.wood_density_kg_m3;
  for (size_t i = 0; i < n; ++i) {
    if (!tree.alive[i]) continue;
    const double l = tree.length_m[i], R = tree.radius_m[i], r = params.tip_ratio * R;
    s.m[i] = d * frustum_volume(l, R, r);                                               // eq. 9
    s.x[i] = to_d(tree.base[i]) + to_d(tree.direction[i]) * frustum_centroid(l, R, r);  // eq. 11
    s.leaf_area_m2[i] = leaf_area(tree, params, i);
    s.p[i] = light_m2.empty() ? s.leaf_area_m2[i] : std::max(0.0, static_cast<double>(light_m2[i]));
  }
  // Parents have smaller ids than their children, so a reverse sweep visits children first.
  for (size_t k = n; k-- > 0;) {
    if (!tree.alive[k]) continue;
    s.M[k] += s.m[k];  // eq. 10 (children already added theirs)
    s.X[k] += s.x[k] * s.m[k];
    s.P[k] += s.p[k];  // eq. 14
    if (k > 0) {
      const size_t j = static_cast<size_t>(tree.parent[k]);
      s.M[j] += s.M[k];
      s.P[j] += s.P[k];
    }
  }
  for (size_t k = n; k-- > 0;) {
    if (!tree.alive[k]) continue;
    // s.X[k] holds x_k m_k + Σ_j X_j M_j once its children are done (eq. 12).
    s.X[k] = s.M[k] > 0.0 ? s.X[k] / s.M[k] : s.x[k];
    if (k > 0) s.X[static_cast<size_t>(tree.parent[k])] += s.X[k] * s.M[k];
  }
  // Eq. 13, with the sign that makes growth oppose the offset of the tree's centre of mass from
  // above the trunk base (§1: "centers the tree's center of mass over the trunk"), measured in
  // trunk radii, then clamped to [−1, 1] (docs/hart_baker.md "Readings").
  const DVec3 offset = horizontal(s.X[0]);
  const double scale = std::max(1e-6, static_cast<double>(tree.radius_m[0]));
  for (size_t i = 0; i < n; ++i) {
    if (!tree.alive[i]) continue;
    if (params.balance) s.o[i] = std::clamp(-glm::dot(to_d(tree.direction[i]), offset) / scale, -1.0, 1.0);
    // Eq. 15's g_i: minimum + balance term (capped at 1) + photosynthesis (lit fraction of the
    // limb's own leaves, with phototropism), scaled by apical dominance per branching order. Only
    // shoots lengthen; a limb with a continuation passes its share on (g_i = 0).
    if (!is_shoot(tree, i)) continue;
    double g = params.min_growth + (params.balance ? params.balance_growth * (1.0 + s.o[i]) : params.balance_growth);
    g = std::min(g, 1.0);
    if (params.phototropism && s.leaf_area_m2[i] > 0.0) {
      g += params.light_growth * std::min(1.0, s.p[i] / s.leaf_area_m2[i]);
    }
    s.g[i] = g * std::pow(static_cast<double>(params.apical_dominance), tree.order[i]);
  }
  for (size_t k = n; k-- > 0;) {
    if (!tree.alive[k]) continue;
    s.G[k] += s.g[k];  // eq. 15
    if (k > 0) s.G[static_cast<size_t>(tree.parent[k])] += s.G[k];
  }
  return s;
}

std::vector<double> reaction_wood_reach(const HartBakerTree& tree, const HartBakerParams& params, const LimbSums& s) {
  const size_t n = tree.size();
  std::vector<double> reach(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    if (!tree.alive[i]) continue;
    const DVec3 dir = to_d(tree.direction[i]);
    const double lever = glm::length(horizontal(s.X[i] - to_d(tree.base[i])));  // X̄_i sin θ_X
    const bool continues = i == 0 || tree.apex[static_cast<size_t>(tree.parent[i])] == static_cast<int32_t>(i);
    const double sin_d =
        continues ? 1.0 : glm::length(glm::cross(dir, to_d(tree.direction[static_cast<size_t>(tree.parent[i])])));
    const double support = supports(tree.radius_m[i], params.wood_density_kg_m3, params.max_height_m);  // F_R / g
    if (lever > 0.0 && support > 0.0 && sin_d > 1e-6) reach[i] = s.M[i] * lever / (support * sin_d);    // eq. 25
  }
  return reach;
}

double reaction_wood_falloff(double u) {
  if (u <= 0.0) return 1.0;
  if (u >= 1.0) return 0.0;
  return (1.0 - u) * (1.0 - u) * (1.0 + 2.0 * u);
}

HartBakerTree make_hart_baker_seedling(const HartBakerParams& params, uint64_t seed) {
  HartBakerTree t;
  t.seed = seed;
  add_limb(t, -1, 0, Vec3(0.0f), Vec3(0, 0, 1), params.seedling_height_m, params.seedling_radius_m);
  return t;
}

namespace {

// Grows every living limb by the year's mass (eq. 16–22): the trunk's radius first, then each limb
// thicker and longer by its share, passing the rest to its children.
void allot_mass(HartBakerTree& tree, const HartBakerParams& params, const LimbSums& s, GrowthReport& report) {
  const size_t n = tree.size();
  const double d = params.wood_density_kg_m3;
  const double H = params.max_height_m;
  const double tau = params.tip_ratio;
  const std::vector<std::vector<int32_t>> children = tree.children();

  // Eq. 16–17. "The first priority is that the trunk be allowed to support its own weight": its
  // new radius is eq. 16's, or more if needed to support the tree plus what the year's
  // photosynthesis can build (B = growth_efficiency · P_0); e_0 = supports(R_0') − M_0, bounded by
  // B (docs/hart_baker.md "Readings").
  const double nutrition = s.P[0];
  const double budget = params.growth_efficiency_kg_m2 * nutrition;
  const double R0_new = std::max(tree.radius_m[0] + params.trunk_growth * nutrition / std::max(s.M[0], 1e-9),
                                 needs_to_support(s.M[0] + budget, d, H));
  const double e0 = std::max(0.0, std::min(supports(R0_new, d, H) - s.M[0], budget));
  report.mass_allotted_kg = e0;

  std::vector<double> e(n, 0.0);
  e[0] = e0;
  for (size_t i = 0; i < n; ++i) {
    if (!tree.alive[i]) continue;
    const double l = tree.length_m[i], R = tree.radius_m[i];
    const double m = s.m[i];
    // Trunk: eq. 16–17's radius. Other limbs: eq. 18, read as "at least the radius that supports
    // what the limb carries plus its share of the new growth", R_i' = max(R_i, needstosupport(M_i +
    // e_i)), never thicker than the limb it grows from (docs/hart_baker.md "Readings"); both as
    // far as the mass the limb is given allows.
    double R_new = R0_new;
    if (i > 0) {
      R_new = std::max(R, needs_to_support(s.M[i] + e[i], d, H));
      R_new = std::min(R_new, std::max(R, static_cast<double>(tree.radius_m[static_cast<size_t>(tree.parent[i])])));
    }
    double m_new = d * frustum_volume(l, R_new, tau * R_new);
    if (m_new - m > e[i]) {
      R_new = m > 0.0 ? R * std::sqrt((m + e[i]) / m) : R;
      m_new = m + e[i];
    }
    double e_rest = std::max(0.0, e[i] - (m_new - m));  // eq. 19
    if (s.G[i] <= 0.0) {
      // Nothing above it grows (its continuation was shed): the limb thickens with the rest.
      if (m_new > 0.0) R_new *= std::sqrt((m_new + e_rest) / m_new);
      m_new += e_rest;
      e_rest = 0.0;
    }
    m_new += s.G[i] > 0.0 ? s.g[i] / s.G[i] * e_rest : 0.0;  // eq. 20
    // Eq. 21, with the radius kept at least l/slenderness: the paper's limbs never bend (§1.2), so
    // nothing else would stop a thin shoot from taking its share as metres of length.
    double l_new = length_for_mass(m_new, R_new, tau, d);
    if (l_new > params.slenderness * R_new) {
      l_new = std::cbrt(m_new * params.slenderness * params.slenderness / (d * frustum_volume(1.0, 1.0, tau)));
      R_new = l_new / params.slenderness;
    }
    tree.radius_m[i] = static_cast<float>(R_new);
    tree.length_m[i] = static_cast<float>(l_new);
    report.mass_added_kg += d * frustum_volume(tree.length_m[i], R_new, tau * R_new) - m;
    for (const int32_t j : children[i])  // eq. 22
      if (tree.alive[static_cast<size_t>(j)] && s.G[i] > 0.0)
        e[static_cast<size_t>(j)] = s.G[static_cast<size_t>(j)] / s.G[i] * e_rest;
  }
}

// Adds the year's reaction wood to every living limb (§5.1) and records its growth ring.
void add_reaction_wood(HartBakerTree& tree, const HartBakerParams& params, const LimbSums& s,
                       const std::vector<float>& old_radius) {
  const size_t n = tree.size();
  // Reaction wood (§5.1). δ_i of eq. 24–25 (reaction_wood_reach, on the grown radii: F_R is the
  // support of this year's base). The year's eccentric growth is reaction_wood·ΔR·min(1, δ_i/R_i) on
  // the side ŷ: towards the load for gymnosperms (compression wood below), away from it for
  // angiosperms (tension wood above).
  const std::vector<double> reach = reaction_wood_reach(tree, params, s);
  for (size_t i = 0; i < n; ++i) {
    if (!tree.alive[i]) continue;
    const DVec3 dir = to_d(tree.direction[i]);
    // The side the supported weight bends the limb toward, across its axis: dir × (v × ẑ) with v the
    // lever (for an upright limb the side toward the load; for a leaning one the underside).
    const DVec3 across = glm::cross(dir, glm::cross(s.X[i] - to_d(tree.base[i]), DVec3(0, 0, 1)));
    const double across_len = glm::length(across);
    if (across_len > 1e-9 && reach[i] > 0.0) {
      const double dR = tree.radius_m[i] - old_radius[i];
      const double amount =
          params.reaction_wood * dR * std::min(1.0, reach[i] / std::max(1e-6, double(tree.radius_m[i])));
      const DVec3 side = (params.wood == WoodClass::Gymnosperm ? 1.0 : -1.0) * across / across_len;
      tree.reaction_m[i] += Vec3(side * (0.5 * amount));
    }
    tree.ring_radius_m[i].push_back(tree.radius_m[i]);
    tree.ring_length_m[i].push_back(tree.length_m[i]);
    tree.ring_offset_m[i].push_back(tree.reaction_m[i]);
  }
}

// Shedding (§4.1 "kills limbs that do not return sufficient photosynthetic nutrition"), from the
// tips inward: each limb's lit fraction is that of its own leaves (p_i over their area), smoothed
// ½ old + ½ new each year, a new limb starting from its parent's. A limb dies when it carries no
// living limb and its leaves are shaded below shed_light, or it has no leaves left; its parent
// is then judged in the same sweep (children have larger ids). So shaded twigs die, a branch dies
// once it is bare, and a branch that still carries lit shoots lives however shaded its base is.
// The trunk's axis is never shed (docs/hart_baker.md "Shedding").
void shed_limbs(HartBakerTree& tree, const HartBakerParams& params, const LimbSums& s,
                const std::vector<float>& light_m2, GrowthReport& report) {
  const size_t n = tree.size();
  if (params.phototropism && !light_m2.empty()) {
    std::vector<int> living_children(n, 0);
    for (size_t i = 1; i < n; ++i)
      if (tree.alive[i]) ++living_children[static_cast<size_t>(tree.parent[i])];
    for (size_t i = n; i-- > 0;) {
      if (!tree.alive[i]) continue;
      if (s.leaf_area_m2[i] > 0.0)
        tree.lit[i] = static_cast<float>(0.5 * tree.lit[i] + 0.5 * std::min(1.0, s.p[i] / s.leaf_area_m2[i]));
      if (tree.order[i] == 0 || living_children[i] > 0 || tree.year - tree.born[i] < params.shed_age) continue;
      if (s.leaf_area_m2[i] <= 0.0 || tree.lit[i] < params.shed_light) {
        tree.alive[i] = 0;
        --living_children[static_cast<size_t>(tree.parent[i])];
        ++report.shed;
      }
    }
  }
}

// The year's node at every shoot tip: a continuation shoot (same order, turned by up to
// apical_var_deg) and lateral buds that break with probability bud_break, at the branching
// angle, turned by the divergence angle each year (phyllotaxis) and spread evenly around the
// limb within a node.
void sprout_buds(HartBakerTree& tree, const HartBakerParams& params, GrowthReport& report) {
  const float branch = radians(params.branch_angle_deg);
  const float spread = radians(params.branch_angle_var_deg);
  const size_t before = tree.size();
  for (size_t i = 0; i < before; ++i) {
    if (!tree.alive[i] || !is_shoot(tree, i)) continue;
    const Vec3 tip = tree.base[i] + tree.direction[i] * tree.length_m[i];
    const float tip_radius = tree.tip_radius(i, params);
    Pcg32 rng(hash_ids(tree.seed, static_cast<uint64_t>(i), 0x5eedu));
    const Vec2 u = uniform2(rng);
    const Vec3 ahead = turn_from(tree.direction[i], radians(params.apical_var_deg) * u.x, kTwoPi * u.y);
    tree.apex[i] = static_cast<int32_t>(tree.size());
    add_limb(tree, static_cast<int32_t>(i), tree.order[i], tip, ahead, params.bud_length_m,
             std::min(params.bud_radius_m, tip_radius));
    ++report.sprouted;
    if (tree.order[i] >= params.max_order) continue;
    // Phyllotaxis along the axis: the node's azimuth turns by the divergence angle from one yearly
    // segment to the next, from a random start per axis.
    int node = 0;
    size_t first = i;
    while (first > 0 && tree.apex[static_cast<size_t>(tree.parent[first])] == static_cast<int32_t>(first)) {
      first = static_cast<size_t>(tree.parent[first]);
      ++node;
    }
    const float axis_phase = kTwoPi * Pcg32(hash_ids(tree.seed, static_cast<uint64_t>(first), 0xa215u)).uniform() +
                             radians(params.divergence_deg) * static_cast<float>(node);
    for (int b = 0; b < params.buds_per_node; ++b) {
      if (rng.uniform() >= params.bud_break) continue;
      const float phi = axis_phase + kTwoPi * static_cast<float>(b) / static_cast<float>(params.buds_per_node);
      const float theta = branch + spread * rng.symmetric();
      add_limb(tree, static_cast<int32_t>(i), static_cast<uint8_t>(tree.order[i] + 1), tip,
               turn_from(tree.direction[i], theta, phi), params.bud_length_m,
               std::min(params.bud_radius_m, 0.8f * tip_radius));
      ++report.sprouted;
    }
  }
}

}  // namespace

GrowthReport grow_hart_baker_year(HartBakerTree& tree, const HartBakerParams& params,
                                  const std::vector<float>& light_m2) {
  const LimbSums s = compute_limb_sums(tree, params, light_m2);
  GrowthReport report;
  const std::vector<float> old_radius = tree.radius_m;
  allot_mass(tree, params, s, report);
  add_reaction_wood(tree, params, s, old_radius);
  ++tree.year;
  shed_limbs(tree, params, s, light_m2, report);
  sprout_buds(tree, params, report);
  return report;
}

void prune_hart_baker_limb(HartBakerTree& tree, int32_t id) {
  if (id <= 0 || static_cast<size_t>(id) >= tree.size())
    throw Error(fmt::format("prune: limb {} is not a branch of this tree (ids 1..{})", id,
                            tree.size() > 0 ? tree.size() - 1 : 0));
  if (!tree.alive[static_cast<size_t>(id)]) throw Error(fmt::format("prune: limb {} is already gone", id));
  kill_subtree(tree, tree.children(), id);
}

TreeLeaves hart_baker_leaves(const HartBakerTree& tree, const HartBakerParams& params) {
  TreeLeaves leaves;
  const Vec3 up(0, 0, 1);
  const float divergence = radians(params.divergence_deg);
  for (size_t i = 0; i < tree.size(); ++i) {
    if (!tree.alive[i]) continue;
    const Vec3 axis = tree.direction[i];
    const Frame f = Frame::from_z(axis);
    const int slots = leaf_slots(tree, params, i);
    for (int k = 0; k < slots; ++k) {
      if (!has_leaf(tree, params, i, k)) continue;
      const float s = (static_cast<float>(k) + 0.5f) * params.leaf_spacing_m;
      const float phi = divergence * static_cast<float>(k);
      const Vec3 blade = std::cos(phi) * f.x + std::sin(phi) * f.y;  // across the limb
      Vec3 normal = up - glm::dot(up, blade) * blade;                // turned about the petiole to face up
      normal = glm::length(normal) > 1e-4f ? glm::normalize(normal) : axis;
      Frame lf;
      lf.z = blade;
      lf.y = normal;
      lf.x = glm::cross(lf.y, lf.z);
      leaves.positions.push_back(tree.base[i] + axis * s + blade * radius_at(tree, params, i, s));
      leaves.frames.push_back(lf);
      leaves.length_m.push_back(params.leaf_length_m);
      leaves.width_m.push_back(params.leaf_width_m);
      leaves.shapes.push_back(LeafShape::Oval);
      leaves.stem.push_back(static_cast<int32_t>(i));
    }
  }
  return leaves;
}

namespace {

// The unit vector halfway between two unit directions (the first if they are opposite).
Vec3 bisector(const Vec3& a, const Vec3& b) {
  const Vec3 h = a + b;
  const float len = glm::length(h);
  return len > 1e-6f ? h / len : a;
}

}  // namespace

TreeModel hart_baker_tree_model(const HartBakerTree& tree, const HartBakerParams& params) {
  TreeModel model;
  std::vector<int32_t> stem_of(tree.size(), -1);
  const std::vector<double> reach = reaction_wood_reach(tree, params, compute_limb_sums(tree, params, {}));
  for (size_t i = 0; i < tree.size(); ++i) {
    if (!tree.alive[i]) continue;
    stem_of[i] = static_cast<int32_t>(model.stems.size());
    TreeStems& st = model.stems;
    const int32_t parent = tree.parent[i] >= 0 ? stem_of[static_cast<size_t>(tree.parent[i])] : -1;
    st.level.push_back(tree.order[i]);
    st.parent.push_back(parent);
    st.clone_of.push_back(-1);
    st.first_section.push_back(static_cast<uint32_t>(model.sections.size()));
    st.length_m.push_back(tree.length_m[i]);
    st.base_radius_m.push_back(tree.radius_m[i]);
    st.offset_m.push_back(parent >= 0 ? glm::length(tree.base[i] - tree.base[static_cast<size_t>(tree.parent[i])])
                                      : 0.0f);
    st.lobes.push_back(0);
    st.lobe_depth.push_back(0.0f);
    // Yearly segments meet in the plane bisecting their axes (which may turn by up to apical_var_deg
    // there): a segment continuing a living limb starts with its first ring in that plane, and the
    // limb ends with a short last piece along the bisector, so both end rings coincide instead of
    // leaving a wedge-shaped notch on the outside of the turn (the shared mesher sets a stem's first
    // ring by its first frame and its last by its last piece).
    const int32_t up = tree.parent[i];
    const bool continues = up >= 0 && tree.apex[static_cast<size_t>(up)] == static_cast<int32_t>(i);
    const Frame f = Frame::from_z(continues ? bisector(tree.direction[static_cast<size_t>(up)], tree.direction[i])
                                            : tree.direction[i]);
    StemSections& sec = model.sections;
    const int32_t apex = tree.apex[i];
    const bool joined = apex >= 0 && tree.alive[static_cast<size_t>(apex)];
    const float l = tree.length_m[i];
    const Vec3 offset = tree.reaction_m[i];
    const Vec3 next_offset = joined ? tree.reaction_m[static_cast<size_t>(apex)] : Vec3(0.0f);
    const float R = tree.radius_m[i];
    const float r = joined ? tree.radius_m[static_cast<size_t>(apex)] : tree.tip_radius(i, params);
    // Eq. 31: the offset times c(s/δ) along the limb, plus the continuation's own offset coming in
    // linearly, on the cone's axis and radius. Sections at s = 0, δ/4, …, δ (while inside the limb)
    // and at the tip.
    // δ at least the limb's base radius (a bulge spans the limb's thickness, also when this year's
    // lever is ~0 but earlier years' offset remains) and at most its length.
    const float delta = glm::length(offset) > 0.0f ? std::clamp(static_cast<float>(reach[i]), std::min(R, l), l) : 0.0f;
    auto add_section = [&](float arc) {
      const float t = l > 0.0f ? arc / l : 0.0f;
      const float c = delta > 0.0f ? static_cast<float>(reaction_wood_falloff(arc / delta)) : 0.0f;
      // The tip is the continuation's base exactly (the limb's length is recomputed from its mass
      // each year, so base + direction·l can differ from it by rounding).
      const Vec3 axis =
          joined && arc >= l ? tree.base[static_cast<size_t>(apex)] : tree.base[i] + tree.direction[i] * arc;
      sec.positions.push_back(axis + offset * c + next_offset * t);
      sec.frames.push_back(f);
      sec.radius_m.push_back(R + (r - R) * t);
      sec.arc_m.push_back(arc);
    };
    uint32_t count = 0;
    add_section(0.0f), ++count;
    if (delta > 0.0f)
      for (int k = 1; k <= kReactionSections; ++k) {
        const float arc = delta * static_cast<float>(k) / kReactionSections;
        if (arc >= 0.999f * l) break;
        add_section(arc), ++count;
      }
    if (joined) {
      const Vec3 along = bisector(tree.direction[i], tree.direction[static_cast<size_t>(apex)]);
      const float eps = std::min(0.5f * r, 0.1f * l);
      const float last_arc = sec.arc_m.back();
      if (l - eps > last_arc && glm::dot(along, tree.direction[i]) < 1.0f) {
        add_section(l);
        const Vec3 tip = sec.positions.back();
        sec.positions.back() = tip - along * eps;
        sec.arc_m.back() = l - eps;
        sec.radius_m.back() = R + (r - R) * (l - eps) / l;
        ++count;
      }
    }
    add_section(l), ++count;
    st.section_count.push_back(count);
  }
  model.leaves = hart_baker_leaves(tree, params);
  for (int32_t& s : model.leaves.stem) s = stem_of[static_cast<size_t>(s)];
  return model;
}

TreeModel make_tree(const HartBakerParams& params, uint64_t seed, const TreeOptions& options) {
  if (params.grown) return hart_baker_tree_model(*params.grown, params);
  HartBakerTree tree = make_hart_baker_seedling(params, seed);
  const int years = options.years > 0 ? options.years : params.years;
  for (int y = 0; y < years; ++y) grow_hart_baker_year(tree, params, {});
  return hart_baker_tree_model(tree, params);
}

}  // namespace sylva
