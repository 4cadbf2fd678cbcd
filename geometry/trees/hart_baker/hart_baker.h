#pragma once
// Hart & Baker, "Structural Simulation of Tree Growth and Response" (seed 004): a developmental
// tree of truncated cones grown one year per iteration from mass, balance, photosynthesis and
// support (§3–§4). Readings of the places the paper leaves open are in docs/hart_baker.md.
//
// This folder holds the growth state and the yearly step only. It never calls the renderer: the
// photosynthesis of eq. 14 arrives as a plain per-limb array (intercepted leaf area, m²) that
// scenes/hart_baker_growth.h computes with the light-view rasterizer of render/light_view.h.
//
// Frames: tree space, metres, Z up, trunk base at the origin (docs/design.md §4). The paper's
// limb frame grows along +y; here a limb's growth direction is its world unit vector `direction`
// (the paper's T_i y), and T_i is the translation to `base` plus the rotation taking +Z to it.

#include "core/params.h"
#include "geometry/trees/tree_model.h"

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

enum class WoodClass : uint8_t {
  Angiosperm,  // tension wood on the upper side (§3.2)
  Gymnosperm,  // compression wood on the lower side
};

// The light-view pass that supplies eq. 14 (read by scenes/, stored here with the species).
struct HartBakerLight {
  int resolution = 256;  // pixels across the window
  // Side of the fixed window (§6.1's "natural aperture ... as a tree might receive if growing in a
  // forest clearing"): the face, toward the light, of a cube of this side standing on the ground
  // around the trunk. 0: the crown's own bounding square.
  float window_m = 0.0f;
  int samples = 1;          // light directions per year (the paper takes one)
  float sun_weight = 0.8f;  // share of directions from the sun's path, the rest from the sky (Greene)
  float latitude_deg = 45.0f;
  int first_day = 120;  // growing season, days of the year (1..365)
  int last_day = 270;
};

// The drawn surface (§5.2): blended joints where laterals leave their parents.
struct HartBakerSurface {
  bool blend = true;                 // polygonise the joints (false: the shared mesher's tubes only)
  float joint_min_radius_m = 0.01f;  // blend a node whose thickest lateral is at least this thick
  float reach = 2.5f;                // the blend fades out this many parent radii from the node
  float fillet = 0.6f;               // the blend adds at most this many lateral radii of wood
  int joint_cells = 24;              // most marching cells across a joint's cube
};

// Bark (§5.4) from the particle flow (§5.3).
enum class BarkKind : uint8_t { Smooth, Spotted, Ribbon };
struct HartBakerBark {
  BarkKind kind = BarkKind::Smooth;
  float spacing_m = 0.03f;     // particle spacing around a limb and step along the flow
  float min_radius_m = 0.02f;  // features only on limbs at least this thick
  float size_m = 0.02f;        // spot width / ribbon width
  float length_m = 0.08f;      // ribbon length (spots: height = size·aspect)
  float aspect = 0.5f;         // spot height over width (the paper's spots stay within 2:1)
  float height_m = 0.003f;     // how far a feature's peak stands above the bark
  float density = 0.7f;        // share of particle positions that carry a feature
  float twist_deg = 8.0f;      // ribbons' random twist about the bark normal
};

// A species: the physics constants of §3.4, the growth rates of §4.1 and the small genotype that
// the paper leaves open (buds, branching and leaves; docs/hart_baker.md "Genotype").
struct HartBakerParams {
  // Physics (§3.4). k of eq. 6 from the tallest possible tree (eq. 8: supports(R, d) = d·v(R, 0, H),
  // k = π·H/3; the paper's H = 300 feet = 91.44 m gives k = π·100 feet; the default is a smaller
  // tree's limit, which gives stouter limbs).
  float wood_density_kg_m3 = 600.0f;  // d
  float max_height_m = 30.0f;         // H of eq. 8
  WoodClass wood = WoodClass::Angiosperm;
  // Growth (§4.1).
  float min_growth = 0.1f;               // g_i's minimum
  float balance_growth = 0.45f;          // g_i += b + b·o_i, capped at 1 (with the minimum)
  float light_growth = 1.0f;             // g_i += light_growth · p_i / (leaf area of limb i)
  float trunk_growth = 0.001f;           // α of eq. 16: trunk radius (m) per (m² of lit leaf / kg of tree)
  float growth_efficiency_kg_m2 = 0.5f;  // new wood per m² of intercepted leaf area per year (bounds eq. 17)
  float tip_ratio = 0.2f;                // r_i / R_i, each limb's taper
  float slenderness = 100.0f;            // largest l_i / R_i a limb grows to (it thickens instead)
  bool balance = true;                   // eq. 13 offsets on (off: o_i = 0)
  bool phototropism = true;              // light term in g_i and shedding (off: the light only feeds eq. 16–17)
  // Genotype (docs/hart_baker.md).
  float divergence_deg = 137.5f;   // phyllotaxis: turn between successive nodes (and leaves)
  float branch_angle_deg = 45.0f;  // between a new limb and its parent
  float branch_angle_var_deg = 8.0f;
  int buds_per_node = 2;          // lateral buds set at each year's node
  float bud_break = 0.7f;         // probability a lateral bud grows into a limb
  float apical_dominance = 0.7f;  // growth rate of an order-n limb scaled by dominance^n
  int max_order = 3;              // deepest branching order
  float apical_var_deg = 4.0f;    // random turn of a year's continuation shoot from its limb
  float seedling_height_m = 0.5f;
  float seedling_radius_m = 0.01f;
  float bud_radius_m = 0.004f;  // base radius of a new limb
  float bud_length_m = 0.1f;
  float leaf_spacing_m = 0.08f;  // along a limb, where its radius is below the threshold
  float leaf_length_m = 0.1f;
  float leaf_width_m = 0.07f;
  float leaf_radius_m = 0.012f;  // leaves only where the limb is thinner than this
  // Shedding (§4.1 "kills limbs that do not return sufficient photosynthetic nutrition"), from the
  // tips inward: a limb at least `shed_age` years old that carries no living limb dies when its
  // own leaves' smoothed lit fraction falls below `shed_light`, or when it has no leaves left.
  float shed_light = 0.2f;
  int shed_age = 1;
  // Reaction wood (§5.1): the share of a year's radius increase laid down eccentrically.
  float reaction_wood = 0.5f;
  // How long the tree grows when a scene uses the species (`sylva grow --years` overrides).
  int years = 20;
  HartBakerLight light;
  HartBakerSurface surface;
  HartBakerBark bark;
  // A grown state to use as is (a saved state file, or the tree scenes/ grew with the light pass);
  // null for a species file, which make_tree grows from the seedling.
  std::shared_ptr<const struct HartBakerTree> grown;

  // Tree-model registry entry (geometry/trees/tree_models.h): `model = "hart-baker"`.
  static constexpr std::string_view kType = "hart-baker";
  static HartBakerParams create(const Params& params, std::vector<std::string>& warnings);
};

// The growth state: Table 1's limb variables as parallel arrays, one entry per limb ever grown
// (ids are stable: a shed or pruned limb stays, marked not alive, so limb ids given to `prune`
// keep their meaning). Limb 0 is the trunk.
struct HartBakerTree {
  uint64_t seed = 0;
  int year = 0;  // iterations done
  // Per limb.
  std::vector<int32_t> parent;  // -1 for the trunk
  std::vector<uint8_t> order;   // branching order, 0 = trunk
  std::vector<uint8_t> alive;   // 0 once shed or pruned
  std::vector<int32_t> born;    // year the limb sprouted (t_i = year − born)
  std::vector<Vec3> base;       // T_i's translation (fixed, §1.2)
  std::vector<Vec3> direction;  // T_i y (fixed)
  std::vector<float> length_m;  // l_i
  std::vector<float> radius_m;  // R_i (base); r_i = tip_ratio · R_i
  std::vector<int32_t> apex;    // the limb continuing this one (its next year's shoot), -1 while a shoot
  std::vector<float> lit;       // smoothed lit fraction of the limb's own leaves (for shedding)
  // Growth rings (§6): R_i at the end of every year since the limb sprouted, the length then, and
  // the cumulative reaction-wood offset of the ring centre (world vector; §5.1, eq. 31).
  std::vector<std::vector<float>> ring_radius_m;
  std::vector<std::vector<float>> ring_length_m;
  std::vector<std::vector<Vec3>> ring_offset_m;
  std::vector<Vec3> reaction_m;  // this limb's accumulated eccentric growth (world vector)

  size_t size() const { return parent.size(); }
  float tip_radius(size_t i, const HartBakerParams& p) const { return p.tip_ratio * radius_m[i]; }
  // J_i, children of every limb (alive or not), in id order.
  std::vector<std::vector<int32_t>> children() const;
};

// Closed forms (§4.1). Volume of a truncated cone of length l, base radius R, tip radius r
// (eq. 9, written as π l (R² + R r + r²)/3, which equals the paper's form and holds at R = r).
double frustum_volume(double l, double R, double r);
// Height of its centre of mass above the base along the axis (eq. 11; l/4 for a cone, r = 0).
double frustum_centroid(double l, double R, double r);
// supports(R, d) = k·d·R² (eq. 6) and its inverse needstosupport(m, d) = √(m/(k·d)) (eq. 7), k from
// max_height_m by eq. 8.
double supports(double R, double d, double max_height_m);
double needs_to_support(double m, double d, double max_height_m);
// The length of a limb of base radius R (tip tip_ratio·R) holding mass m: eq. 9 inverted (eq. 21
// for a cone, tip_ratio = 0).
double length_for_mass(double m, double R, double tip_ratio, double d);

// Whether limb i is a growing shoot (no continuation yet): only shoots lengthen (eq. 20–21).
inline bool is_shoot(const HartBakerTree& t, size_t i) { return t.apex[i] < 0; }

// The per-limb quantities of one iteration (steps 1–4 of §4.1), computed from the state.
struct LimbSums {
  std::vector<double> m, M;          // eq. 9, 10
  std::vector<DVec3> x, X;           // eq. 11, 12 (world)
  std::vector<double> o;             // eq. 13 (clamped)
  std::vector<double> p, P;          // eq. 14
  std::vector<double> g, G;          // eq. 15
  std::vector<double> leaf_area_m2;  // leaf area of each limb's own leaves
};

// Steps 1–4: mass, centre of mass, offsets, photosynthesis and growth rates. `light_m2` is the
// intercepted leaf area per limb from the light pass (size() entries), or empty when there is no
// light pass, in which case every leaf counts as fully lit. Dead limbs contribute nothing.
LimbSums compute_limb_sums(const HartBakerTree& tree, const HartBakerParams& params,
                           const std::vector<float>& light_m2);

// Reaction wood's reach δ_i along each limb (§5.1, eq. 24–25 as written):
//   W_i X̄_i sin θ_X = δ_i F_R sin θ_d  ⇒  δ_i = W_i X̄_i sin θ_X / (F_R sin θ_d),
// with W_i = M_i g the weight the limb supports, X̄_i sin θ_X the horizontal lever from the limb's
// base to X̄_i (θ_X its angle from above the base), F_R = supports(R_i) g the support of the
// base's wood (eq. 6, "the reaction wood has the same strength as the wood at the branch's base"),
// and θ_d the limb's angle to its parent (90° for the trunk and for an axis' own yearly
// continuation, which bends with the axis). g cancels. 0 where there is nothing to resist (no
// lever, no wood, or a limb along its parent) and for dead limbs. From the sums of this state.
std::vector<double> reaction_wood_reach(const HartBakerTree& tree, const HartBakerParams& params, const LimbSums& sums);

// Eq. 31's falloff c(t l / δ) of the reaction-wood bulge along a limb, at u = arc / δ: the paper
// leaves c open; Sylva takes 1 − smoothstep, (1 − u)²(1 + 2u) on [0, 1] and 0 beyond, so the bulge
// is full and flat at the base, ends at δ and meets the plain limb there without a crease.
double reaction_wood_falloff(double u);

// What one year's step did, for tests and statistics.
struct GrowthReport {
  double mass_allotted_kg = 0;  // e_0 of eq. 17
  double mass_added_kg = 0;     // Σ m_i' − m_i over the limbs that existed before the step
  int sprouted = 0;
  int shed = 0;
};

// The first state: a trunk of the seedling's height and radius.
HartBakerTree make_hart_baker_seedling(const HartBakerParams& params, uint64_t seed);

// One year (§4.1 steps 1–5, eq. 9–22; reaction wood §5.1 eq. 24–25; rings §6), then shedding of
// unproductive limbs (phototropism on, light given) and the year's node at every shoot tip: a
// continuation shoot and lateral buds. Pure given (state, params, light).
GrowthReport grow_hart_baker_year(HartBakerTree& tree, const HartBakerParams& params,
                                  const std::vector<float>& light_m2);

// The user prunes limb `id` and what it supports between years (§6.1). Throws sylva::Error for an
// unknown id, the trunk, or a limb already gone.
void prune_hart_baker_limb(HartBakerTree& tree, int32_t id);

// Leaves of the living limbs (§4.1 "polygons that sprout from limbs at fixed intervals where their
// radius is sufficiently small ... oriented about their stem axis to face up"), in the TreeLeaves
// convention; `stem` holds the limb id.
TreeLeaves hart_baker_leaves(const HartBakerTree& tree, const HartBakerParams& params);

// The state as a TreeModel: one stem per living limb (base and tip sections; `stem` of each leaf
// maps to the stem index, not the limb id), so the shared mesher turns it into tubes and leaves.
// The base section carries the limb's reaction wood (§5.1, eq. 31): it is the outer ring, radius
// R_i centred on the ring centre's offset, so the side ŷ stands out by the offset and the other
// side falls back by as much (eq. 31's bulge of Δr = twice the offset on a concentric core of
// R_i − offset, as the rings show it). Along the limb the offset falls off as eq. 31's
// c(t l_i / δ_i) (reaction_wood_falloff, δ_i from reaction_wood_reach, at most the limb's length),
// drawn by kReactionSections sections over [0, δ_i]; the tip section is the base section of the
// continuation (whose own offset comes in linearly along the segment), so the yearly segments of an
// axis join without a step in radius or centre (docs/hart_baker.md "Surface").
inline constexpr int kReactionSections = 4;
TreeModel hart_baker_tree_model(const HartBakerTree& tree, const HartBakerParams& params);

// Tree-model registry function. The model a scene sees is grown by scenes/ with the light pass
// (make_species_model); on its own, geometry has no light, so this grows options.years (else
// params.years) with every leaf counted as fully lit — pure and seeded. A grown state is used as is.
TreeModel make_tree(const HartBakerParams& params, uint64_t seed, const TreeOptions& options);

}  // namespace sylva
