// The aspen grammar's parameter schema: every AspenGrammarParams field by name, range-checked.

#include "geometry/trees/lsystem/aspen_grammar.h"

#include <fmt/core.h>

namespace sylva {

AspenGrammarParams AspenGrammarParams::create(const Params& params, std::vector<std::string>&) {
  AspenGrammarParams p;
  const RealField reals[] = {
      {"height", &p.height, 1e-3, 1e6},
      {"diameter", &p.diameter, 1e-4, 1e5},
      {"unit_m", &p.unit_m, 1e-6, 1e3},
      {"point_spacing", &p.point_spacing, 0.1, 1e3},
      {"point_spacing_generation", &p.point_spacing_generation, 0, 1e5},
      {"bump", &p.bump, 0, 10},
      {"trunk_shrinkage", &p.trunk_shrinkage, 0, 1},
      {"branch_shrinkage", &p.branch_shrinkage, 0, 1},
      {"min_diameter", &p.min_diameter, 0, 1e5},
      {"branch_probability", &p.branch_probability, 0, 1},
      {"dead_probability", &p.dead_probability, 0, 1},
      {"dead_length", &p.dead_length, 0, 1},
      {"length_ratio", &p.length_ratio, 0, 0.95},
      {"length_child_term", &p.length_child_term, 0, 1e5},
      {"length_generation_term", &p.length_generation_term, 0, 1e5},
      {"min_length", &p.min_length, 1e-3, 1e6},
      {"diameter_contraction_min", &p.diameter_contraction_min, 0, 1},
      {"diameter_contraction_max", &p.diameter_contraction_max, 0, 1},
      {"fork_probability", &p.fork_probability, 0, 1},
      {"divergence_deg", &p.divergence_deg, -360, 360},
      {"divergence_noise_deg", &p.divergence_noise_deg, 0, 180},
      {"branch_angle_base_deg", &p.branch_angle_base_deg, 0, 180},
      {"branch_angle_child_rad", &p.branch_angle_child_rad, -10, 10},
      {"branch_angle_generation_rad", &p.branch_angle_generation_rad, -10, 10},
      {"min_branch_angle_rad", &p.min_branch_angle_rad, 0, kPi},
      {"sag", &p.sag, -1, 1},
      {"droop_limit", &p.droop_limit, -1, 1},
      {"cluster_radius_m", &p.cluster_radius_m, 0, 100},
      {"leaf_length_m", &p.leaf_length_m, 0, 10},
      {"leaf_width_m", &p.leaf_width_m, 0, 10},
  };
  const IntField ints[] = {
      {"generations", &p.generations, 0, 8},
      {"bump_every", &p.bump_every, 0, 1000},
      {"first_trunk_point", &p.first_trunk_point, 1, 10000},
      {"shoot_generation", &p.shoot_generation, 0, 8},
      {"leaves_per_cluster", &p.leaves_per_cluster, 0, 1000},
  };
  params.read_fields(reals, ints);
  if (params.has("leaf_shape")) {
    const std::string name = params.string("leaf_shape");
    const std::optional<LeafShape> shape = leaf_shape_from_name(name);
    if (!shape) params.fail("leaf_shape", fmt::format("unknown leaf_shape \"{}\"", name));
    p.leaf_shape = *shape;
  }
  if (p.branch_probability + p.dead_probability > 1.0f)
    params.fail(params.has("dead_probability") ? "dead_probability" : "branch_probability",
                "branch_probability + dead_probability must be at most 1");
  if (p.diameter_contraction_min > p.diameter_contraction_max)
    params.fail(params.has("diameter_contraction_max") ? "diameter_contraction_max" : "diameter_contraction_min",
                "diameter_contraction_min must not exceed diameter_contraction_max");
  params.check_unused();
  return p;
}

}  // namespace sylva
