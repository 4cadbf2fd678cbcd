#pragma once
// Checks shared by the material types: reflectances and transmittances are physical.

#include "core/spectrum.h"

#include <string>

namespace sylva {

// Throws sylva::Error naming material `name` if `s` leaves [0, 1] anywhere.
void check_unit_range(const std::string& name, const char* what, const DenseSpectrum& s);
// Throws sylva::Error naming material `name` if ρ + τ > 1 anywhere on the given face.
void check_energy(const std::string& name, const DenseSpectrum& r, const DenseSpectrum& t, const char* face);

}  // namespace sylva
