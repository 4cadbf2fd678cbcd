#pragma once
// The parameters of a real camera applied to a render (docs/sensors.md): its optics, how its
// detectors sample the rendered image, and its detector and electronics. Plain data with defaults
// (a 12-bit machine-vision camera behind an f/2.8 lens); read from a scene's [sensor] section by
// read_sensor_params, which starts from a named preset (sensor/presets.h) when one is given.

#include "core/params.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sylva {

// The optics' transfer function, in detector pitches (docs/sensors.md, "Optics").
struct OpticsParams {
  double f_number = 2.8;
  double obscuration = 0.0;            // central obscuration: its diameter over the aperture's, [0, 0.9]
  double transmittance = 0.9;          // of the optics, in band
  double defocus_px = 0.0;             // 1/e radius of the Gaussian defocus spot (IBSM eq. 3-25), pitches
  double jitter_rms_px = 0.0;          // RMS line-of-sight jitter during the integration (IBSM eq. 3-28), pitches
  double smear_px = 0.0;               // linear drift along x during the integration (IBSM eq. 3-29), pitches
  std::filesystem::path otf_file;      // a radial OTF: cycles/mm at the focal plane, OTF (IBSM §3.2.6)
  std::vector<double> otf_cyc_per_mm;  // the file's table, ascending (empty: none)
  std::vector<double> otf_value;
};

// How detectors sample the render: each detector integrates the blurred radiance over its square
// of `ratio` render pixels on a side (docs/sensors.md, "Sampling").
struct SamplingParams {
  double pitch_um = 3.45;        // detector pitch
  double focal_length_mm = 0.0;  // > 0: ratio = (pitch / focal length) / render pixel angle
  double oversample = 2.0;       // the ratio when focal_length_mm is 0
};

// The detector and its electronics (docs/sensors.md, "Detector").
struct DetectorParams {
  double qe = 0.6;                                       // quantum efficiency, every channel
  std::vector<std::pair<std::string, double>> qe_bands;  // per band or channel name, replacing `qe`
  double integration_time_ms = 1.0;
  bool auto_exposure = false;  // integration time: the 99th percentile at 70 % of the full well
  double full_well_e = 10500.0;
  double read_noise_e = 2.3;
  double dark_current_e_per_s = 5.0;
  double prnu = 0.005;  // photo-response non-uniformity, RMS fraction of the signal
  double dsnu_e = 1.0;  // dark-signal non-uniformity, RMS electrons
  double gain_e_per_dn = 2.56;
  double offset_dn = 16.0;  // black level
  int adc_bits = 12;
  bool shot_noise = true;
  // Thermal detectors (thermal = true): the noise is given as temperatures at the channel's
  // centre wavelength and reference_temperature_k; the ADC spans temperature_min_k..max_k.
  bool thermal = false;
  double netd_mk = 50.0;
  double fpn_mk = 20.0;       // fixed-pattern noise after correction, RMS
  double nuc_residual = 0.0;  // gain residual of the non-uniformity correction, RMS fraction of L - L_ref
  double reference_temperature_k = 300.0;
  double temperature_min_k = 240.0;
  double temperature_max_k = 340.0;
};

struct SensorParams {
  std::string preset;  // the preset it started from ("" if none)
  std::string source;  // where the preset's figures come from
  OpticsParams optics;
  SamplingParams sampling;
  DetectorParams detector;
  uint64_t seed = 1;                   // the fixed patterns (PRNU, DSNU, FPN, NUC): fixed over frames
  std::optional<uint64_t> noise_seed;  // temporal noise; default: hashed from the render's seed
};

// [sensor]: `preset = "NAME"` first (its values become the defaults), then every key; unknown keys,
// bad values and unreadable OTF files are `file:line: what was expected` (ParseError).
SensorParams read_sensor_params(const Params& table);

}  // namespace sylva
