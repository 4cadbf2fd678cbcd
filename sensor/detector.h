#pragma once
// The detector and its electronics (docs/sensors.md, "Detector"): the mean radiance over each
// detector becomes photo-electrons, fixed-pattern and temporal noise, a clipped charge and digital
// numbers; thermal detectors take their noise as temperatures. Every random number is a hash of
// (seed, channel, detector, kind), so the result depends on nothing else (not the thread count);
// the fixed patterns use SensorParams::seed alone, so they stay the same over frames.

#include "core/planck.h"  // planck_radiance, planck_radiance_dt: the thermal channels' scale
#include "sensor/otf.h"
#include "sensor/sensor_params.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sylva {

// How a channel's digital numbers map back to radiance: L = radiance_per_dn × (DN − dn_offset)
// (the mean over a detector; the dark signal's mean is in dn_offset).
struct ChannelCalibration {
  std::string channel;
  double qe = 0;                      // the quantum efficiency used (0 for thermal channels)
  double electrons_per_radiance = 0;  // e⁻ per unit radiance in the integration time (0: thermal)
  double radiance_per_dn = 0;
  double dn_offset = 0;
  double saturation_radiance = 0;  // the radiance that reaches the full well or the ADC's top
};

// Photo-electrons per second per unit channel radiance (W·m⁻²·sr⁻¹·nm⁻¹) on one detector: the
// camera equation E = π L τ (1 − η²) / (1 + 4N²) (Schott 1997, as pyBSM), over the pitch², the
// channel's equivalent width, at its centre wavelength's photon energy, times `qe`.
double electron_rate_per_radiance(const SensorParams& params, const SensorChannel& channel, double qe);

// The quantum efficiency of `channel`: its entry in qe_bands by channel name, else by band name,
// else DetectorParams::qe.
double channel_qe(const DetectorParams& detector, const SensorChannel& channel);

// The calibration of a channel at integration time `time_s`.
ChannelCalibration calibrate_channel(const SensorParams& params, const SensorChannel& channel, double time_s);

// The digital numbers of one channel: `radiance` is the mean over each detector (width × height);
// `channel_index` keeps the channels' noise apart; `noise_seed` seeds the temporal noise.
std::vector<float> detect_channel(const std::vector<float>& radiance, int width, int height, int channel_index,
                                  const SensorParams& params, const ChannelCalibration& calibration,
                                  const SensorChannel& channel, double time_s, uint64_t noise_seed);

// A standard normal number and a Poisson count (exact below a mean of 30, else the normal
// approximation with continuity, whose variance is the mean), from one hashed stream.
double hashed_normal(uint64_t key);
double hashed_poisson(uint64_t key, double mean);

}  // namespace sylva
