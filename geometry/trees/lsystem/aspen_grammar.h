#pragma once
// The quaking-aspen branching grammar (seed 002, the aspen thesis, Chapter 6): the EBNF grammar
//
//   <root>        -> <linear_pt> <linear_tail>
//   <linear_tail> -> <linear_pt> <linear_tail> | <leaf_clus> | Null
//   <linear_pt>   -> <circle_pt>^8
//   <circle_pt>   -> <bark> | <bark> <root>
//   <leaf_clus>   -> <leaf_pt> <leaf_tail>      <leaf_tail> -> <leaf_pt> <leaf_tail> | Null
//
// expanded by the thesis's aspen semantic routines: linear points (6.1) spaced by diameter and
// generation, bumping every fifth point, child directions from branch and divergence angles
// (6.2–6.7), girth shrinkage (6.9, 6.10), da Vinci's area rule at forks (6.8), diameter (6.13) and
// golden-ratio length (6.12) contraction, branch angles falling with the child number (6.14), dead
// branches, self-adjustment and lifting, leaf clusters at the tips. Lengths are in the thesis's
// units (its constants 4, 3 and 6.0 are in them); `unit_m` converts to metres. Sylva's readings
// of the open places are docs/lsystems.md.

#include "core/params.h"
#include "geometry/leaf_shape.h"
#include "geometry/trees/tree_model.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

struct AspenGrammarParams {
  // Registry entry (geometry/trees/tree_models.h): `model = "aspen-grammar"`; the parameters are
  // the fields below by name, each range-checked (aspen_grammar_params.cpp).
  static constexpr std::string_view kType = "aspen-grammar";
  static AspenGrammarParams create(const Params& params, std::vector<std::string>& warnings);

  // The thesis's inputs (Ch. 7: "height, diameter, coordinates, and seeds").
  float height = 260;    // trunk length, units
  float diameter = 7;    // trunk diameter at the root, units
  float unit_m = 0.05f;  // metres per unit
  int generations = 3;   // deepest generation (trunk = 0, its branches = 1)
  // Linear points (6.1): distance = point_spacing × diameter + point_spacing_generation × generation.
  float point_spacing = 3.0f;
  float point_spacing_generation = 2.0f;
  int bump_every = 5;  // "every fifth linear point is a candidate for bumping"
  float bump = 0.35f;  // bump amplitude of each minor direction component, in diameters
  // Girth (6.9, 6.10): the diameter shrinks along an object by shrinkage × arc / length.
  float trunk_shrinkage = 0.8f;
  float branch_shrinkage = 0.2f;
  // Child branching: none before the trunk's fifth point or where the diameter is below the
  // minimum; otherwise a branch, a dead branch or nothing.
  int first_trunk_point = 5;
  float min_diameter = 0.3f;  // units
  float branch_probability = 0.6f;
  float dead_probability = 0.12f;
  float dead_length = 0.5f;  // a dead branch's length as a fraction of a living one's
  // Length contraction (6.12): Lc = ratio × Lp − child_number × child_term − generation × gen_term.
  float length_ratio = 0.618f;
  float length_child_term = 4;
  float length_generation_term = 3;
  float min_length = 6;  // self-adjustment: shorter branches are lengthened to this (units)
  // Diameter contraction (6.13): Dc = Dp − Dp × U(min, max).
  float diameter_contraction_min = 0.25f;
  float diameter_contraction_max = 0.45f;
  // Bifurcation at a living branch's tip; the two children share the area (6.8, α = 2).
  float fork_probability = 0.1f;
  // Divergence (Ch. 5, 6): successive children turn about their parent by this ± noise.
  float divergence_deg = 138;
  float divergence_noise_deg = 20;
  // Branch angle (6.14), read in radians: Ab = base − (child_term × child + gen_term × generation).
  float branch_angle_base_deg = 85;
  float branch_angle_child_rad = 0.04f;
  float branch_angle_generation_rad = 0.05f;
  float min_branch_angle_rad = 0.1f;  // self-adjustment
  // Lifting: each point bends the direction down by `sag` (gravity); a direction whose vertical
  // component falls below `droop_limit` is lifted back to it.
  float sag = 0.03f;
  float droop_limit = -0.25f;
  // Leaf clusters at the tips of living branches (generation ≥ 1) and at every linear point of
  // living branches of generation ≥ shoot_generation (their short shoots; 0 = none).
  int shoot_generation = 0;
  int leaves_per_cluster = 10;
  float cluster_radius_m = 0.15f;
  float leaf_length_m = 0.07f;
  float leaf_width_m = 0.065f;
  LeafShape leaf_shape = LeafShape::Oval;
};

// What the semantic routines decided for each child object, for tests and diagnostics.
struct AspenChildRecord {
  int stem = 0;  // the child's stem index in the model
  int parent = 0;
  int generation = 0;
  int child_number = 0;  // 1 for a stem's first child; 0 for a fork at a tip
  bool dead = false;
  bool fork = false;
  float divergence_step_deg = 0;  // azimuth advance from the parent's previous child (0 for the first)
  float branch_angle_rad = 0;
  float diameter_ratio = 0;  // child root diameter / parent diameter at the branch point
  float length = 0;          // units
};

struct AspenGrammarTrace {
  std::vector<AspenChildRecord> children;
};

// Grows one aspen. Pure: the same params and seed give a bit-identical model. Stems carry the
// `dead` flags. Throws sylva::Error ("tree too large: ...") past 200,000 stems or
// 4 million cross-sections.
TreeModel make_aspen_grammar_tree(const AspenGrammarParams& params, uint64_t seed, AspenGrammarTrace* trace = nullptr);

// The registry's generator: the options (wind, quality) do not apply to this model.
inline TreeModel make_tree(const AspenGrammarParams& params, uint64_t seed, const TreeOptions&) {
  return make_aspen_grammar_tree(params, seed);
}

}  // namespace sylva
