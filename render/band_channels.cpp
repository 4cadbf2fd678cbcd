#include "render/band_channels.h"

#include "core/error.h"

namespace sylva {

const char* quantity_name(Quantity q) { return q == Quantity::reflectance ? "reflectance" : "radiance"; }

Quantity parse_quantity(const std::string& name) {
  if (name == "radiance") return Quantity::radiance;
  if (name == "reflectance") return Quantity::reflectance;
  throw Error("quantity must be \"radiance\" or \"reflectance\", not \"" + name + "\"");
}

std::vector<float> channel_irradiance(const Environment& environment, const std::vector<Band>& bands) {
  const DenseSpectrum e = environment.horizontal_irradiance();
  std::vector<float> out;
  for (const Band& b : bands)
    for (const DenseSpectrum& w : b.weights) out.push_back(static_cast<float>(e.integral_product(w)));
  return out;
}

size_t band_channel_count(const std::vector<Band>& bands) {
  size_t n = 0;
  for (const Band& b : bands) n += b.channels.size();
  return n;
}

BandChannels::BandChannels(const std::vector<Band>& bands, const Environment& environment, Quantity quantity) {
  for (const Band& b : bands)
    for (size_t c = 0; c < b.channels.size(); ++c) {
      names.push_back(b.channels[c]);
      weights.push_back(&b.weights[c]);
    }
  irradiance = channel_irradiance(environment, bands);
  for (size_t c = 0; c < names.size(); ++c) {
    if (quantity == Quantity::reflectance && !(irradiance[c] > 0))
      throw Error("reflectance: channel " + names[c] + " receives no irradiance from the sun and sky");
    scale.push_back(quantity == Quantity::reflectance ? kPi / irradiance[c] : 1.0f);
  }
}

double BandChannels::weigh(size_t c, const SampledSpectrum& s, const SampledWavelengths& wl) const {
  double v = 0;
  for (int i = 0; i < kLambdaCount; ++i) v += s[i] * weights[c]->eval(wl.lambda_nm[i]) / wl.pdf[i];
  return v / kLambdaCount;
}

}  // namespace sylva
