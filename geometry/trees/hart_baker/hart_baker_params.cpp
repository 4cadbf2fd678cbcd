// The Hart–Baker species schema (docs/hart_baker.md): every HartBakerParams field by name,
// range-checked, and the [light] table of the light-view pass.

#include "geometry/trees/hart_baker/hart_baker.h"

#include <fmt/core.h>

namespace sylva {

HartBakerParams HartBakerParams::create(const Params& params, std::vector<std::string>&) {
  HartBakerParams p;
  const RealField reals[] = {
      {"wood_density", &p.wood_density_kg_m3, 10, 2000},
      {"max_height_m", &p.max_height_m, 0.1, 1000},
      {"min_growth", &p.min_growth, 0, 1},
      {"balance_growth", &p.balance_growth, 0, 1},
      {"light_growth", &p.light_growth, 0, 100},
      {"trunk_growth", &p.trunk_growth, 0, 10},
      {"growth_efficiency", &p.growth_efficiency_kg_m2, 0, 100},
      {"tip_ratio", &p.tip_ratio, 0, 1},
      {"slenderness", &p.slenderness, 1, 10000},
      {"divergence_deg", &p.divergence_deg, -360, 360},
      {"branch_angle_deg", &p.branch_angle_deg, 0, 180},
      {"branch_angle_var_deg", &p.branch_angle_var_deg, 0, 90},
      {"bud_break", &p.bud_break, 0, 1},
      {"apical_dominance", &p.apical_dominance, 0.01, 1},
      {"apical_var_deg", &p.apical_var_deg, 0, 90},
      {"seedling_height_m", &p.seedling_height_m, 0.001, 100},
      {"seedling_radius_m", &p.seedling_radius_m, 1e-4, 10},
      {"bud_radius_m", &p.bud_radius_m, 1e-5, 1},
      {"bud_length_m", &p.bud_length_m, 1e-4, 10},
      {"leaf_spacing_m", &p.leaf_spacing_m, 1e-3, 10},
      {"leaf_length_m", &p.leaf_length_m, 1e-3, 10},
      {"leaf_width_m", &p.leaf_width_m, 1e-3, 10},
      {"leaf_radius_m", &p.leaf_radius_m, 0, 10},
      {"shed_light", &p.shed_light, 0, 1},
      {"reaction_wood", &p.reaction_wood, 0, 1},
  };
  const IntField ints[] = {
      {"buds_per_node", &p.buds_per_node, 0, 12},
      {"max_order", &p.max_order, 0, 8},
      {"shed_age", &p.shed_age, 1, 1000},
      {"years", &p.years, 0, 500},
  };
  params.read_fields(reals, ints);
  p.balance = params.boolean("balance", p.balance);
  p.phototropism = params.boolean("phototropism", p.phototropism);
  const std::string wood = params.string("wood", "angiosperm");
  if (wood == "angiosperm")
    p.wood = WoodClass::Angiosperm;
  else if (wood == "gymnosperm")
    p.wood = WoodClass::Gymnosperm;
  else
    params.fail("wood", fmt::format("wood = \"{}\": expected \"angiosperm\" or \"gymnosperm\"", wood));
  if (const Params* light = params.table("light")) {
    HartBakerLight& l = p.light;
    l.resolution = static_cast<int>(light->integer("resolution", l.resolution, 16, 8192));
    l.samples = static_cast<int>(light->integer("samples", l.samples, 1, 1024));
    l.window_m = light->real("window_m", l.window_m, 0, 1000);
    l.sun_weight = light->real("sun_weight", l.sun_weight, 0, 1);
    l.latitude_deg = light->real("latitude_deg", l.latitude_deg, -90, 90);
    l.first_day = static_cast<int>(light->integer("first_day", l.first_day, 1, 365));
    l.last_day = static_cast<int>(light->integer("last_day", l.last_day, 1, 365));
    if (l.last_day < l.first_day) light->fail("last_day", "last_day must not be before first_day");
    light->check_unused();
  }
  if (const Params* surface = params.table("surface")) {
    HartBakerSurface& f = p.surface;
    f.blend = surface->boolean("blend", f.blend);
    f.joint_min_radius_m = surface->real("joint_min_radius_m", f.joint_min_radius_m, 0, 10);
    f.reach = surface->real("reach", f.reach, 1.2, 10);
    f.fillet = surface->real("fillet", f.fillet, 0, 5);
    f.joint_cells = static_cast<int>(surface->integer("joint_cells", f.joint_cells, 6, 64));
    surface->check_unused();
  }
  if (const Params* bark = params.table("bark")) {
    HartBakerBark& b = p.bark;
    const std::string kind = bark->string("kind", "smooth");
    if (kind == "smooth")
      b.kind = BarkKind::Smooth;
    else if (kind == "spotted")
      b.kind = BarkKind::Spotted;
    else if (kind == "ribbon")
      b.kind = BarkKind::Ribbon;
    else
      bark->fail("kind", fmt::format("kind = \"{}\": expected \"smooth\", \"spotted\" or \"ribbon\"", kind));
    b.spacing_m = bark->real("spacing_m", b.spacing_m, 1e-3, 1);
    b.min_radius_m = bark->real("min_radius_m", b.min_radius_m, 0, 10);
    b.size_m = bark->real("size_m", b.size_m, 1e-4, 1);
    b.length_m = bark->real("length_m", b.length_m, 1e-4, 10);
    b.aspect = bark->real("aspect", b.aspect, 0.1, 2);
    b.height_m = bark->real("height_m", b.height_m, 0, 0.1);
    b.density = bark->real("density", b.density, 0, 1);
    b.twist_deg = bark->real("twist_deg", b.twist_deg, 0, 90);
    bark->check_unused();
  }
  params.check_unused();
  return p;
}

}  // namespace sylva
