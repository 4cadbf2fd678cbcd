#include "sensor/detector.h"

#include "core/hash.h"
#include "core/rng.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sylva {

namespace {

constexpr double kPlanck = 6.62607015e-34;  // J·s
constexpr double kLight = 299792458.0;      // m/s

// The kinds of random number per detector.
enum Kind : uint64_t { kPrnu = 1, kDsnu, kFpn, kNuc, kShot, kRead, kNetd };

uint64_t key_of(uint64_t seed, int channel, size_t pixel, Kind kind) {
  return hash_ids(seed, static_cast<uint64_t>(channel), static_cast<uint64_t>(pixel), static_cast<uint64_t>(kind));
}

double adc_max(const DetectorParams& d) { return std::ldexp(1.0, d.adc_bits) - 1.0; }

float quantise(double dn, double top) { return static_cast<float>(std::clamp(std::round(dn), 0.0, top)); }

}  // namespace

double hashed_normal(uint64_t key) {
  Pcg32 rng(mix64(key));
  // Box–Muller, u1 in (0, 1].
  const double u1 = 1.0 - rng.uniform_double(), u2 = rng.uniform_double();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

double hashed_poisson(uint64_t key, double mean) {
  if (mean <= 0) return 0;
  if (mean >= 30.0) return std::max(0.0, std::round(mean + std::sqrt(mean) * hashed_normal(key)));
  Pcg32 rng(mix64(key ^ 0x9e3779b97f4a7c15ull));
  // Inversion: walk the CDF.
  const double u = rng.uniform_double();
  double p = std::exp(-mean), cdf = p;
  int k = 0;
  while (u > cdf && k < 1000) {
    ++k;
    p *= mean / k;
    cdf += p;
  }
  return k;
}

double electron_rate_per_radiance(const SensorParams& params, const SensorChannel& channel, double qe) {
  const OpticsParams& o = params.optics;
  const double n = o.f_number, eta = o.obscuration, pitch_m = params.sampling.pitch_um * 1e-6;
  const double irradiance_per_radiance = std::numbers::pi * o.transmittance * (1.0 - eta * eta) / (1.0 + 4.0 * n * n);
  const double photon_energy_j = kPlanck * kLight / (channel.centre_nm * 1e-9);
  return qe * irradiance_per_radiance * pitch_m * pitch_m * channel.equivalent_width_nm / photon_energy_j;
}

double channel_qe(const DetectorParams& d, const SensorChannel& channel) {
  for (const auto& [name, qe] : d.qe_bands)
    if (name == channel.name) return qe;
  for (const auto& [name, qe] : d.qe_bands)
    if (name == channel.band) return qe;
  return d.qe;
}

ChannelCalibration calibrate_channel(const SensorParams& params, const SensorChannel& channel, double time_s) {
  const DetectorParams& d = params.detector;
  ChannelCalibration c;
  c.channel = channel.name;
  if (d.thermal) {
    const double lo = planck_radiance(channel.centre_nm, d.temperature_min_k);
    const double hi = planck_radiance(channel.centre_nm, d.temperature_max_k);
    c.radiance_per_dn = (hi - lo) / adc_max(d);
    c.dn_offset = -lo / c.radiance_per_dn;
    c.saturation_radiance = hi;
    return c;
  }
  c.qe = channel_qe(d, channel);
  c.electrons_per_radiance = electron_rate_per_radiance(params, channel, c.qe) * time_s;
  c.radiance_per_dn = d.gain_e_per_dn / c.electrons_per_radiance;
  c.dn_offset = d.offset_dn + d.dark_current_e_per_s * time_s / d.gain_e_per_dn;
  const double top_e = std::min(d.full_well_e, (adc_max(d) - d.offset_dn) * d.gain_e_per_dn);
  c.saturation_radiance = std::max(0.0, top_e - d.dark_current_e_per_s * time_s) / c.electrons_per_radiance;
  return c;
}

std::vector<float> detect_channel(const std::vector<float>& radiance, int width, int height, int channel_index,
                                  const SensorParams& params, const ChannelCalibration& cal,
                                  const SensorChannel& channel, double time_s, uint64_t noise_seed) {
  const DetectorParams& d = params.detector;
  const double top = adc_max(d);
  const uint64_t fixed = params.seed;
  std::vector<float> dn(radiance.size());
  const double slope = d.thermal ? planck_radiance_dt(channel.centre_nm, d.reference_temperature_k) : 0.0;
  const double l_ref = d.thermal ? planck_radiance(channel.centre_nm, d.reference_temperature_k) : 0.0;
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      const double l = radiance[i];
      if (d.thermal) {
        // Kelvin of noise as radiance through dL/dT at the reference temperature.
        const double noisy = l + (l - l_ref) * d.nuc_residual * hashed_normal(key_of(fixed, channel_index, i, kNuc)) +
                             d.fpn_mk * 1e-3 * slope * hashed_normal(key_of(fixed, channel_index, i, kFpn)) +
                             d.netd_mk * 1e-3 * slope * hashed_normal(key_of(noise_seed, channel_index, i, kNetd));
        dn[i] = quantise(noisy / cal.radiance_per_dn + cal.dn_offset, top);
        continue;
      }
      const double prnu = 1.0 + d.prnu * hashed_normal(key_of(fixed, channel_index, i, kPrnu));
      const double dark =
          d.dark_current_e_per_s * time_s + d.dsnu_e * hashed_normal(key_of(fixed, channel_index, i, kDsnu));
      const double mean_e = std::max(0.0, cal.electrons_per_radiance * std::max(0.0, l) * prnu + dark);
      double e = d.shot_noise ? hashed_poisson(key_of(noise_seed, channel_index, i, kShot), mean_e) : mean_e;
      e = std::min(e, d.full_well_e) + d.read_noise_e * hashed_normal(key_of(noise_seed, channel_index, i, kRead));
      dn[i] = quantise(e / d.gain_e_per_dn + d.offset_dn, top);
    }
  });
  return dn;
}

}  // namespace sylva
