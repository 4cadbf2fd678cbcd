#include "core/band.h"

#include "core/data_path.h"
#include "core/error.h"
#include "core/table.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace sylva {

namespace {

DenseSpectrum normalised(const DenseSpectrum& s) {
  DenseSpectrum r = s;
  const double integral = s.integral();
  if (!(integral > 0)) throw Error("spectral response has zero integral");
  r *= static_cast<float>(1.0 / integral);
  return r;
}

struct SrfSource {
  const char* prefix;  // band name prefix, e.g. "S2A_"
  const char* file;
};
constexpr SrfSource kSatellites[] = {
    {"S2A_", "srf/Sentinel_2A_Spectral_Response.tsv"},
    {"S2B_", "srf/Sentinel_2B_Spectral_Response.tsv"},
    {"L8_", "srf/Landsat_8_Spectral_Response.tsv"},
    {"L9_", "srf/Landsat_9_Spectral_Response.tsv"},
};
struct CameraBand {
  const char* name;
  const char* column;
};
constexpr CameraBand kCameraBands[] = {
    {"nir", "Basler_acA2500-20gm_850nm_filt"},
    {"red_edge", "Basler_acA2500-20gm_730nm_filt"},
    {"mono", "Basler_acA2500-20gm_mono"},
};
constexpr const char* kCameraFile = "srf/helios_camera_nir_srf.csv";

// Landsat 8/9 OLI band numbers → the SRF table's column names.
constexpr std::pair<const char*, const char*> kLandsatBands[] = {
    {"B1", "CoastalAerosol"}, {"B2", "Blue"},  {"B3", "Green"}, {"B4", "Red"},    {"B5", "NIR"},
    {"B6", "SWIR1"},          {"B7", "SWIR2"}, {"B8", "Pan"},   {"B9", "Cirrus"},
};

std::string srf_column(const std::string& prefix, const std::string& band) {
  if (prefix == "L8_" || prefix == "L9_")
    for (const auto& [number, column] : kLandsatBands)
      if (band == number) return column;
  return band;
}

}  // namespace

Band make_rgb_band() {
  // XYZ normalised by ∫ȳ so an equal-energy spectrum of 1 has Y = 1; then XYZ → linear Rec.709
  // (IEC 61966-2-1 matrix).
  const float k = static_cast<float>(1.0 / cie_y().integral());
  constexpr float m[3][3] = {{3.2404542f, -1.5371385f, -0.4985314f},
                             {-0.9692660f, 1.8760108f, 0.0415560f},
                             {0.0556434f, -0.2040259f, 1.0572252f}};
  Band b;
  b.name = "rgb";
  b.channels = {"R", "G", "B"};
  for (const auto& row : m) {
    DenseSpectrum w;
    for (int i = 0; i < kLambdaSamples; ++i)
      w[i] = k * (row[0] * cie_x()[i] + row[1] * cie_y()[i] + row[2] * cie_z()[i]);
    b.weights.push_back(w);
  }
  b.importance = normalised(cie_x() + cie_y() + cie_z());
  b.source = "CIE 1931 2-degree colour-matching functions (data/cie1931_2deg_cmf_1nm.csv) -> linear Rec.709, D65";
  return b;
}

Band make_srf_band(const std::string& name, const DenseSpectrum& response_in) {
  // Measured responses carry small negative noise floors (e.g. Landsat OLI's RSR tables); a
  // response cannot be negative, so those values are set to zero.
  DenseSpectrum response = response_in;
  for (int i = 0; i < kLambdaSamples; ++i) response[i] = std::max(0.0f, response[i]);
  // The response is read on the spectral grid, zero outside its table: a band beyond the grid has
  // no weight on it, and one whose response is still above 0.1 % of its peak at an end of the grid
  // crosses it and would be cut off there without a word (a table that starts at 300 nm with zero
  // there keeps a trace at the first sample, which the grid's box filter spreads: not a crossing).
  const std::string range = fmt::format("{:.0f}–{:.0f} nm", kLambdaMin, kLambdaMax);
  if (!(response.integral() > 0))
    throw Error(
        fmt::format("band '{}': its spectral response has no weight in Sylva's spectral range, {} "
                    "(thermal bands beyond {:.0f} nm are not supported yet)",
                    name, range, kLambdaMax));
  const float edge = 1e-3f * response.max_value();
  if (response[0] > edge || response[kLambdaSamples - 1] > edge)
    throw Error(
        fmt::format("band '{}': its spectral response is non-zero at {:.0f} nm, an end of Sylva's spectral "
                    "range {}; a band must lie inside the range, its response falling to zero there",
                    name, response[0] > edge ? kLambdaMin : kLambdaMax, range));
  Band b;
  b.name = name;
  b.channels = {name + ".Y"};
  b.weights = {normalised(response)};
  b.importance = b.weights[0];
  return b;
}

Band load_band(const std::string& name, const std::filesystem::path& file, const std::string& column) {
  Band b = make_srf_band(name, load_spectrum(file, column, Extrapolate::Zero));
  b.source = file.filename().string() + ", column " + column;
  return b;
}

ChannelSummary summarise_channel(const DenseSpectrum& weight) {
  DenseSpectrum s;
  for (int i = 0; i < kLambdaSamples; ++i) s[i] = std::max(0.0f, weight[i]);
  ChannelSummary out;
  const double area = s.integral(), peak = s.max_value();
  if (!(area > 0)) return out;
  DenseSpectrum lambda;
  for (int i = 0; i < kLambdaSamples; ++i) lambda[i] = kLambdaMin + static_cast<float>(i);
  out.centre_nm = s.integral_product(lambda) / area;
  out.equivalent_width_nm = area / peak;
  // Outermost half-maximum crossings, interpolated between 1 nm samples.
  const double half = 0.5 * peak;
  int lo = 0, hi = kLambdaSamples - 1;
  while (s[lo] < half) ++lo;
  while (s[hi] < half) --hi;
  const double left = lo == 0 ? kLambdaMin : kLambdaMin + lo - (s[lo] - half) / (s[lo] - s[lo - 1]);
  const double right =
      hi == kLambdaSamples - 1 ? kLambdaMin + hi : kLambdaMin + hi + (s[hi] - half) / (s[hi] - s[hi + 1]);
  out.fwhm_nm = right - left;
  return out;
}

std::vector<std::string> known_band_names() {
  std::vector<std::string> names = {"rgb"};
  for (const auto& c : kCameraBands) names.emplace_back(c.name);
  for (const auto& s : kSatellites) {
    const Table t = read_table(data_file(s.file));
    if (std::string(s.prefix)[0] == 'L') {
      for (const auto& [number, column] : kLandsatBands) names.push_back(s.prefix + std::string(number));
    } else {
      for (size_t c = 1; c < t.header.size(); ++c) names.push_back(s.prefix + t.header[c]);
    }
  }
  return names;
}

Band resolve_band(const std::string& name) {
  if (name == "rgb") return make_rgb_band();
  for (const auto& c : kCameraBands)
    if (name == c.name) return load_band(name, data_file(kCameraFile), c.column);
  for (const auto& s : kSatellites) {
    const std::string prefix = s.prefix;
    if (name.rfind(prefix, 0) == 0) {
      const Table t = read_table(data_file(s.file));
      const std::string column = srf_column(prefix, name.substr(prefix.size()));
      for (size_t c = 1; c < t.header.size(); ++c)
        if (t.header[c] == column) {
          Band b = make_srf_band(name, DenseSpectrum::from_samples(t.columns[0], t.columns[c], Extrapolate::Zero));
          b.source = std::filesystem::path(s.file).filename().string() + ", column " + column;
          return b;
        }
    }
  }
  std::string list;
  for (const auto& n : known_band_names()) list += (list.empty() ? "" : ", ") + n;
  throw Error("unknown band '" + name + "' (known: " + list + ")");
}

}  // namespace sylva
