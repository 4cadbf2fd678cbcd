#include "sensor/presets.h"

namespace sylva {

namespace {

SensorPreset make_preset(std::string name, std::string source, SensorParams p) {
  p.preset = name;
  p.source = source;
  return {std::move(name), std::move(source), std::move(p)};
}

// A 12-bit machine-vision camera behind an f/2.8 lens (issue 44's example).
SensorPreset machine_vision() {
  SensorParams p;
  p.optics.f_number = 2.8;
  p.sampling.pitch_um = 3.45;
  p.sampling.oversample = 2.0;
  DetectorParams& d = p.detector;
  d.qe = 0.64;
  d.full_well_e = 10500.0;
  d.read_noise_e = 2.3;
  d.dark_current_e_per_s = 5.0;
  d.prnu = 0.005;
  d.dsnu_e = 1.0;
  d.adc_bits = 12;
  d.gain_e_per_dn = 10500.0 / 4095.0;
  d.offset_dn = 16.0;
  d.auto_exposure = true;
  return make_preset("machine_vision_12bit",
                     "Sony IMX264 (Basler acA2440-20gm EMVA 1288 data: 3.45 um pitch, QE 64 % at 545 nm, saturation "
                     "10.5 ke-, temporal dark noise 2.3 e-, 12 bit) behind an f/2.8 lens; dark current, PRNU and "
                     "DSNU assumed",
                     p);
}

// Sentinel-2 MSI, a 10 m band: coarse detectors (8 render pixels each by default), f/4.
SensorPreset sentinel2() {
  SensorParams p;
  p.optics.f_number = 4.0;
  p.optics.transmittance = 0.8;
  p.sampling.pitch_um = 7.5;
  p.sampling.oversample = 8.0;
  DetectorParams& d = p.detector;
  d.qe = 0.7;
  d.full_well_e = 200000.0;
  d.read_noise_e = 40.0;
  d.dark_current_e_per_s = 1000.0;
  d.prnu = 0.002;
  d.dsnu_e = 20.0;
  d.adc_bits = 12;
  d.gain_e_per_dn = 200000.0 / 4095.0;
  d.offset_dn = 0.0;
  d.integration_time_ms = 1.5;
  d.auto_exposure = true;
  return make_preset("sentinel2_msi_10m",
                     "ESA Sentinel-2 User Handbook (2015) and Gascon et al. 2017, Remote Sens. 9(6) 584: 150 mm pupil, "
                     "600 mm focal length (f/4), 7.5 um VNIR pitch, 12-bit quantisation; full well, noise and "
                     "non-uniformity assumed; the detector covers `oversample` render pixels, not 10 m",
                     p);
}

// A phone camera: small pixels, an 8-bit output and a short exposure, so shot noise shows.
SensorPreset phone() {
  SensorParams p;
  p.optics.f_number = 1.8;
  p.optics.transmittance = 0.85;
  p.optics.jitter_rms_px = 0.3;
  p.sampling.pitch_um = 1.4;
  p.sampling.oversample = 2.0;
  DetectorParams& d = p.detector;
  d.qe = 0.5;
  d.full_well_e = 4500.0;
  d.read_noise_e = 2.5;
  d.dark_current_e_per_s = 20.0;
  d.prnu = 0.01;
  d.dsnu_e = 2.0;
  d.adc_bits = 8;
  d.gain_e_per_dn = 4500.0 / 255.0;
  d.offset_dn = 4.0;
  d.auto_exposure = true;
  return make_preset("phone_8bit",
                     "representative of a 12 MP phone camera (Sony IMX363 class: 1.4 um pixels, f/1.8); full well, "
                     "noise, 0.3 px hand jitter and the 8-bit output assumed, not from a data sheet",
                     p);
}

// An uncooled LWIR microbolometer core, 640 x 512, 12 um, NETD 50 mK.
SensorPreset lwir() {
  SensorParams p;
  p.optics.f_number = 1.0;
  p.optics.transmittance = 0.9;
  p.sampling.pitch_um = 12.0;
  p.sampling.oversample = 2.0;
  DetectorParams& d = p.detector;
  d.thermal = true;
  d.netd_mk = 50.0;
  d.fpn_mk = 20.0;
  d.nuc_residual = 0.002;
  d.adc_bits = 14;
  d.reference_temperature_k = 300.0;
  d.temperature_min_k = 240.0;
  d.temperature_max_k = 340.0;
  return make_preset("lwir_640_50mk",
                     "FLIR Boson 640 product data sheet: 640 x 512, 12 um pitch, NETD < 50 mK, 14-bit output, f/1.0 "
                     "lens; FPN and NUC residual assumed",
                     p);
}

}  // namespace

const std::vector<SensorPreset>& sensor_presets() {
  static const std::vector<SensorPreset> presets{machine_vision(), sentinel2(), phone(), lwir()};
  return presets;
}

const SensorPreset* find_sensor_preset(const std::string& name) {
  for (const SensorPreset& p : sensor_presets())
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace sylva
