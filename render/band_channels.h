#pragma once
// The channels a render or a plot measurement writes, set up once from its bands (core/band.h):
// each band's channels in order, their spectral response weights, the sun and sky's band-weighted
// horizontal irradiance and the factor each channel's radiance is multiplied by. The renderer
// (render/renderer.h) and the plot sensor (render/sensors/plot_sensor.h) both start from it.

#include "core/band.h"
#include "render/lights/lights.h"

#include <string>
#include <vector>

namespace sylva {

// What a band channel holds (docs/radiometry.md): the band-weighted spectral radiance
// (W·m⁻²·sr⁻¹·nm⁻¹), or the reflectance factor π·L_c / E_c, where E_c is the band-weighted
// irradiance on a horizontal plane from the same sun and sky (Environment::horizontal_irradiance).
enum class Quantity { radiance, reflectance };

// "radiance" / "reflectance"; parse_quantity throws sylva::Error for anything else.
const char* quantity_name(Quantity q);
Quantity parse_quantity(const std::string& name);

// E_c = ∫ E(λ) w_c(λ) dλ for each channel of `bands`, band after band: the irradiance on a
// horizontal plane from `environment`, weighted like the channel (W·m⁻²·nm⁻¹ for sensor bands).
std::vector<float> channel_irradiance(const Environment& environment, const std::vector<Band>& bands);

// The channels of `bands`, band after band. `weights` point into the bands, which must outlive it.
struct BandChannels {
  std::vector<std::string> names;
  std::vector<const DenseSpectrum*> weights;  // w_c(λ)
  std::vector<float> irradiance;              // E_c (channel_irradiance)
  std::vector<float> scale;                   // π / E_c for reflectance, 1 for radiance

  BandChannels() = default;
  // Throws sylva::Error when `quantity` is reflectance and a channel receives no irradiance.
  BandChannels(const std::vector<Band>& bands, const Environment& environment, Quantity quantity);
  size_t size() const { return names.size(); }
  // Σ_i s_i w_c(λ_i) / p(λ_i) / n: the band-weighted estimate of spectrum `s` for channel c.
  double weigh(size_t c, const SampledSpectrum& s, const SampledWavelengths& wl) const;
};

// The number of channels of `bands`.
size_t band_channel_count(const std::vector<Band>& bands);

}  // namespace sylva
