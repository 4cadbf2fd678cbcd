// What a sensed image records: sensor_attributes (the EXR header) and sensor_json (the sidecar).
#include "sensor/sensor.h"

#include <fmt/core.h>

#include <string>

namespace sylva {

namespace {

std::string number(double v) { return fmt::format("{:.9g}", v); }

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(c));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// Every parameter as (key, value text), in a fixed order.
std::vector<std::pair<std::string, std::string>> parameter_list(const SensorParams& p) {
  const OpticsParams& o = p.optics;
  const DetectorParams& d = p.detector;
  std::vector<std::pair<std::string, std::string>> v{
      {"preset", p.preset},
      {"source", p.source},
      {"f_number", number(o.f_number)},
      {"obscuration", number(o.obscuration)},
      {"transmittance", number(o.transmittance)},
      {"defocus_px", number(o.defocus_px)},
      {"jitter_rms_px", number(o.jitter_rms_px)},
      {"smear_px", number(o.smear_px)},
      {"otf_file", o.otf_file.string()},
      {"pitch_um", number(p.sampling.pitch_um)},
      {"focal_length_mm", number(p.sampling.focal_length_mm)},
      {"oversample", number(p.sampling.oversample)},
      {"qe", number(d.qe)},
      {"auto_exposure", d.auto_exposure ? "true" : "false"},
      {"full_well_e", number(d.full_well_e)},
      {"read_noise_e", number(d.read_noise_e)},
      {"dark_current_e_per_s", number(d.dark_current_e_per_s)},
      {"prnu", number(d.prnu)},
      {"dsnu_e", number(d.dsnu_e)},
      {"gain_e_per_dn", number(d.gain_e_per_dn)},
      {"offset_dn", number(d.offset_dn)},
      {"adc_bits", std::to_string(d.adc_bits)},
      {"shot_noise", d.shot_noise ? "true" : "false"},
      {"thermal", d.thermal ? "true" : "false"},
  };
  for (const auto& [name, qe] : d.qe_bands) v.emplace_back("qe." + name, number(qe));
  if (d.thermal) {
    v.emplace_back("netd_mk", number(d.netd_mk));
    v.emplace_back("fpn_mk", number(d.fpn_mk));
    v.emplace_back("nuc_residual", number(d.nuc_residual));
    v.emplace_back("reference_temperature_k", number(d.reference_temperature_k));
    v.emplace_back("temperature_min_k", number(d.temperature_min_k));
    v.emplace_back("temperature_max_k", number(d.temperature_max_k));
  }
  return v;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> sensor_attributes(const SensedImage& s, const SensorParams& p) {
  std::vector<std::pair<std::string, std::string>> a;
  for (auto& [key, value] : parameter_list(p)) a.emplace_back("sylva:sensor:" + key, value);
  a.emplace_back("sylva:sensor:seed", std::to_string(p.seed));
  a.emplace_back("sylva:sensor:noise_seed", std::to_string(s.noise_seed));
  a.emplace_back("sylva:sensor:integration_time_s", number(s.integration_time_s));
  a.emplace_back("sylva:sensor:render_pixels_per_detector", number(s.grid.ratio));
  a.emplace_back("sylva:sensor:ifov_urad", number(s.ifov_rad * 1e6));
  a.emplace_back("sylva:sensor:gsd_m", number(s.gsd_m));
  a.emplace_back("sylva:sensor:effective_focal_length_mm", number(s.focal_length_mm));
  for (const ChannelCalibration& c : s.calibration)
    a.emplace_back("sylva:sensor:calibration:" + c.channel,
                   fmt::format("radiance = {} * (DN - {}); qe {}; saturation radiance {}", number(c.radiance_per_dn),
                               number(c.dn_offset), number(c.qe), number(c.saturation_radiance)));
  return a;
}

std::string sensor_json(const SensedImage& s, const SensorParams& p) {
  std::string j = "{\n  \"parameters\": {";
  bool first = true;
  for (auto& [key, value] : parameter_list(p)) {
    j += fmt::format("{}\n    {}: {}", first ? "" : ",", json_string(key), json_string(value));
    first = false;
  }
  j += "\n  },\n";
  j += fmt::format("  \"seed\": {},\n  \"noise_seed\": {},\n", p.seed, s.noise_seed);
  j += fmt::format("  \"detectors\": [{}, {}],\n  \"render_pixels_per_detector\": {},\n", s.grid.width, s.grid.height,
                   number(s.grid.ratio));
  j += fmt::format("  \"integration_time_s\": {},\n  \"ifov_urad\": {},\n  \"gsd_m\": {},\n",
                   number(s.integration_time_s), number(s.ifov_rad * 1e6), number(s.gsd_m));
  j += fmt::format("  \"effective_focal_length_mm\": {},\n  \"calibration\": [", number(s.focal_length_mm));
  for (size_t i = 0; i < s.calibration.size(); ++i) {
    const ChannelCalibration& c = s.calibration[i];
    j += fmt::format(
        "{}\n    {{\"channel\": {}, \"radiance_per_dn\": {}, \"dn_offset\": {}, \"qe\": {}, "
        "\"electrons_per_radiance\": {}, \"saturation_radiance\": {}}}",
        i == 0 ? "" : ",", json_string(c.channel), number(c.radiance_per_dn), number(c.dn_offset), number(c.qe),
        number(c.electrons_per_radiance), number(c.saturation_radiance));
  }
  j += "\n  ]\n}\n";
  return j;
}

}  // namespace sylva
