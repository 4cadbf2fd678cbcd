#pragma once
// The optical transfer function of a camera at one channel, in cycles per detector pitch
// (docs/sensors.md, "Optics"). Every factor is real and even in (u, v), so the blur it gives keeps
// a real image real and its sum unchanged (OTF(0, 0) = 1).

#include "core/spectrum.h"
#include "sensor/sensor_params.h"

#include <string>
#include <vector>

namespace sylva {

// What the sensor model needs of a render channel: where its response lies.
struct SensorChannel {
  std::string name;                    // the EXR channel: "R", "nir.Y"
  std::string band;                    // its band: "rgb", "nir"
  double centre_nm = 550.0;            // response-weighted mean wavelength
  double equivalent_width_nm = 100.0;  // ∫S / max S
  std::vector<double> lambda_nm;       // samples of the positive response, for the polychromatic OTF
  std::vector<double> weight;          // (sum 1)
};

// The channel's summary and ~16 samples of its positive response max(w, 0).
SensorChannel describe_channel(const std::string& name, const std::string& band, const DenseSpectrum& weight);
// A channel of one wavelength (tests, arrays handed in without a band).
SensorChannel monochromatic_channel(const std::string& name, double lambda_nm, double equivalent_width_nm);

// Diffraction by a circular aperture with a central obscuration `eta` (diameter ratio) at
// normalised frequency nu = frequency / (D / λ) (IBSM eq. 3-20; O'Neill 1956); eta = 0 gives the
// clear aperture's (2/π)(acos ν − ν√(1−ν²)).
double obscured_aperture_otf(double nu, double eta);

// The optics' OTF at (u, v) cycles per detector pitch for `channel`: diffraction averaged over the
// channel's response (cut-off p / (λ N) cycles per pitch at f-number N), Gaussian defocus, jitter,
// linear smear along x and the OTF file's radial table (linear, held beyond its last row).
double optics_otf(const OpticsParams& optics, double pitch_um, const SensorChannel& channel, double u, double v);

// The detector footprint: a square of one pitch, sinc(u) sinc(v).
double footprint_mtf(double u, double v);

// optics_otf × footprint_mtf: what the sensed image's MTF should be.
double system_otf(const OpticsParams& optics, double pitch_um, const SensorChannel& channel, double u, double v);

}  // namespace sylva
