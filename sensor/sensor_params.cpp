#include "sensor/sensor_params.h"

#include "core/error.h"
#include "core/table.h"
#include "sensor/presets.h"

#include <fmt/core.h>

#include <cmath>
#include <cstdint>
#include <string>

namespace sylva {

namespace {

std::string preset_names() {
  std::string names;
  for (const SensorPreset& p : sensor_presets()) names += (names.empty() ? "" : ", ") + p.name;
  return names;
}

// A radial OTF table: first column cycles/mm at the focal plane (ascending, from 0), second the OTF.
void read_otf_file(const Params& t, OpticsParams& o) {
  o.otf_file = t.file_path("otf_file");
  Table table;
  try {
    table = read_table(o.otf_file);
  } catch (const Error& e) {
    t.fail("otf_file", fmt::format("otf_file: {}", e.what()));
  }
  if (table.columns.size() < 2 || table.rows() < 2)
    t.fail("otf_file", fmt::format("otf_file {}: expected two columns (cycles/mm at the focal plane, OTF) and at "
                                   "least two rows",
                                   o.otf_file.string()));
  o.otf_cyc_per_mm = table.columns[0];
  o.otf_value = table.columns[1];
  for (size_t i = 0; i < o.otf_cyc_per_mm.size(); ++i) {
    const bool ascending = i == 0 ? o.otf_cyc_per_mm[0] >= 0 : o.otf_cyc_per_mm[i] > o.otf_cyc_per_mm[i - 1];
    if (!ascending || !(std::abs(o.otf_value[i]) <= 1.0))
      t.fail("otf_file", fmt::format("otf_file {}: row {}: expected frequencies ascending from 0 and OTF values in "
                                     "[-1, 1]",
                                     o.otf_file.string(), i + 1));
  }
}

void read_optics(const Params& t, OpticsParams& o) {
  o.f_number = t.number("f_number", o.f_number, 0.5, 100.0);
  o.obscuration = t.number("obscuration", o.obscuration, 0.0, 0.9);
  o.transmittance = t.number("transmittance", o.transmittance, 1e-3, 1.0);
  o.defocus_px = t.number("defocus_px", o.defocus_px, 0.0, 100.0);
  o.jitter_rms_px = t.number("jitter_rms_px", o.jitter_rms_px, 0.0, 100.0);
  o.smear_px = t.number("smear_px", o.smear_px, 0.0, 100.0);
  if (!t.string("otf_file", "").empty()) read_otf_file(t, o);
}

void read_qe(const Params& t, DetectorParams& d) {
  const ParamValue* v = t.get("qe");
  if (v == nullptr) return;
  if (v->is_number()) {
    d.qe = t.number("qe", d.qe, 1e-4, 1.0);
    d.qe_bands.clear();
    return;
  }
  if (v->kind != ParamValue::Kind::Table)
    t.fail_at(*v,
              "qe: expected a number in (0, 1] or a table of them by band or channel, e.g. { rgb = 0.6, nir = "
              "0.3 }");
  const Params& q = *v->table;
  d.qe_bands.clear();
  for (const std::string& name : q.names()) d.qe_bands.emplace_back(name, q.number(name, 0.5, 1e-4, 1.0));
}

void read_detector(const Params& t, DetectorParams& d) {
  read_qe(t, d);
  d.integration_time_ms = t.number("integration_time_ms", d.integration_time_ms, 1e-6, 1e6);
  d.auto_exposure = t.boolean("auto_exposure", d.auto_exposure);
  d.full_well_e = t.number("full_well_e", d.full_well_e, 1.0, 1e9);
  d.read_noise_e = t.number("read_noise_e", d.read_noise_e, 0.0, 1e6);
  d.dark_current_e_per_s = t.number("dark_current_e_per_s", d.dark_current_e_per_s, 0.0, 1e9);
  d.prnu = t.number("prnu", d.prnu, 0.0, 0.5);
  d.dsnu_e = t.number("dsnu_e", d.dsnu_e, 0.0, 1e6);
  d.gain_e_per_dn = t.number("gain_e_per_dn", d.gain_e_per_dn, 1e-6, 1e9);
  d.offset_dn = t.number("offset_dn", d.offset_dn, 0.0, 65535.0);
  d.adc_bits = static_cast<int>(t.integer("adc_bits", d.adc_bits, 1, 24));
  d.shot_noise = t.boolean("shot_noise", d.shot_noise);
  d.thermal = t.boolean("thermal", d.thermal);
  d.netd_mk = t.number("netd_mk", d.netd_mk, 0.0, 1e5);
  d.fpn_mk = t.number("fpn_mk", d.fpn_mk, 0.0, 1e5);
  d.nuc_residual = t.number("nuc_residual", d.nuc_residual, 0.0, 0.5);
  d.reference_temperature_k = t.number("reference_temperature_k", d.reference_temperature_k, 150.0, 1000.0);
  d.temperature_min_k = t.number("temperature_min_k", d.temperature_min_k, 100.0, 2000.0);
  d.temperature_max_k = t.number("temperature_max_k", d.temperature_max_k, 100.0, 2000.0);
  if (d.thermal && !(d.temperature_max_k > d.temperature_min_k))
    t.fail("temperature_max_k", "temperature_max_k: expected a temperature above temperature_min_k");
  if (!d.thermal && d.offset_dn > std::ldexp(1.0, d.adc_bits) - 1)
    t.fail("offset_dn",
           fmt::format("offset_dn: expected at most {} (adc_bits = {})", std::ldexp(1.0, d.adc_bits) - 1, d.adc_bits));
}

}  // namespace

SensorParams read_sensor_params(const Params& t) {
  SensorParams p;
  if (const std::string name = t.string("preset", ""); !name.empty()) {
    const SensorPreset* preset = find_sensor_preset(name);
    if (preset == nullptr)
      t.fail("preset", fmt::format("unknown sensor preset '{}' (expected one of: {})", name, preset_names()));
    p = preset->params;
  }
  read_optics(t, p.optics);
  SamplingParams& s = p.sampling;
  s.pitch_um = t.number("pitch_um", s.pitch_um, 0.1, 1000.0);
  const bool focal = t.has("focal_length_mm"), oversample = t.has("oversample");
  if (focal && oversample)
    t.fail("oversample", "give focal_length_mm or oversample, not both (the other follows from the camera)");
  s.focal_length_mm = t.number("focal_length_mm", s.focal_length_mm, 0.0, 1e6);
  s.oversample = t.number("oversample", s.oversample, 1.0, 64.0);
  if (oversample) s.focal_length_mm = 0.0;
  read_detector(t, p.detector);
  p.seed = static_cast<uint64_t>(t.integer("seed", static_cast<int64_t>(p.seed), 0, INT64_MAX));
  if (const int64_t n = t.integer("noise_seed", -1, -1, INT64_MAX); n >= 0) p.noise_seed = static_cast<uint64_t>(n);
  t.check_unused();
  return p;
}

}  // namespace sylva
