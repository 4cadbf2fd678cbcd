#include "render/materials/leaf.h"

#include "core/error.h"
#include "core/prospect.h"
#include "render/materials/material_checks.h"

namespace sylva {

namespace {

// PROSPECT-D leaf optics (Féret et al. 2017) from the biochemical parameters in `p`.
LeafMaterial prospect_leaf(const std::string& name, const Params& p) {
  p.check_keys({"N", "Cab", "Car", "Ant", "Cbrown", "Cw", "Cm"});
  ProspectParams pp;
  pp.N = p.real("N", pp.N, 1.0, 4.0);
  pp.Cab = p.real("Cab", pp.Cab, 0.0, 200.0);
  pp.Car = p.real("Car", pp.Car, 0.0, 50.0);
  pp.Ant = p.real("Ant", pp.Ant, 0.0, 50.0);
  pp.Cbrown = p.real("Cbrown", pp.Cbrown, 0.0, 5.0);
  pp.Cw = p.real("Cw", pp.Cw, 0.0, 0.2);
  pp.Cm = p.real("Cm", pp.Cm, 0.0, 0.1);
  const LeafOptics o = prospect_d(pp);
  const std::vector<double> l(o.lambda_nm.begin(), o.lambda_nm.end());
  const DenseSpectrum rho =
      DenseSpectrum::from_samples(l, {o.reflectance.begin(), o.reflectance.end()}, Extrapolate::Clamp);
  const DenseSpectrum tau =
      DenseSpectrum::from_samples(l, {o.transmittance.begin(), o.transmittance.end()}, Extrapolate::Clamp);
  return make_leaf(name, rho, tau);
}

LeafMaterial tabulated_leaf(const std::string& name, const Params& m) {
  if (!m.has("reflectance") || !m.has("transmittance"))
    m.fail("leaf material '" + name + "' needs reflectance and transmittance (or prospect = {...})");
  const DenseSpectrum rf = m.spectrum("reflectance", Extrapolate::Clamp);
  const DenseSpectrum tf = m.spectrum("transmittance", Extrapolate::Clamp);
  const std::optional<DenseSpectrum> rb = m.optional_spectrum("back_reflectance", Extrapolate::Clamp);
  const std::optional<DenseSpectrum> tb = m.optional_spectrum("back_transmittance", Extrapolate::Clamp);
  return make_leaf(name, rf, tf, rb ? *rb : rf, tb ? *tb : tf);
}

}  // namespace

LeafMaterial make_leaf(const std::string& name, const DenseSpectrum& reflectance, const DenseSpectrum& transmittance) {
  return make_leaf(name, reflectance, transmittance, reflectance, transmittance);
}

LeafMaterial make_leaf(const std::string& name, const DenseSpectrum& rf, const DenseSpectrum& tf,
                       const DenseSpectrum& rb, const DenseSpectrum& tb) {
  check_unit_range(name, "reflectance", rf);
  check_unit_range(name, "transmittance", tf);
  check_unit_range(name, "back reflectance", rb);
  check_unit_range(name, "back transmittance", tb);
  check_energy(name, rf, tf, "front");
  check_energy(name, rb, tb, "back");
  return LeafMaterial{{rf}, {tf}, {rb}, {tb}};
}

LeafMaterial LeafMaterial::create(const std::string& name, const Params& params) {
  try {
    if (const Params* p = params.table("prospect")) {
      if (params.has("reflectance") || params.has("transmittance"))
        params.fail("give either prospect = {...} or reflectance/transmittance, not both");
      return prospect_leaf(name, *p);
    }
    return tabulated_leaf(name, params);
  } catch (const ParseError&) {
    throw;
  } catch (const Error& e) {
    params.fail(e.what());
  }
}

}  // namespace sylva
