#pragma once
// Bands: what a film channel measures. A band is a set of channels, each a weighting function
// w_c(λ) such that the channel value is ∫ L(λ) w_c(λ) dλ:
//  - `rgb`: CIE 1931 colour matching → XYZ (normalised so a constant spectrum of 1 has Y = 1)
//    → linear Rec.709 primaries (D65 white); channels R, G, B.
//  - any sensor band from a tabulated relative spectral response S(λ): w = S / ∫S, one channel
//    `<band>.Y`, so the value is the SRF-weighted mean spectral radiance (W·m⁻²·sr⁻¹·nm⁻¹).
// Adding a band is data, not code: name a column of an SRF table (data/srf/) or a user file.

#include "core/sampling.h"
#include "core/spectrum.h"

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

struct Band {
  std::string name;                    // "rgb", "nir", "S2A_B8", ...
  std::vector<std::string> channels;   // EXR channel names: "R","G","B" or "<name>.Y"
  std::vector<DenseSpectrum> weights;  // w_c(λ), one per channel
  DenseSpectrum importance;            // ≥ 0, ∫ = 1: where this band needs wavelength samples
  std::string source;                  // where the response comes from (data file, standard)
};

// Where a channel is sensitive, from the positive part S = max(w, 0) of its weighting function
// (docs/radiometry.md): centre = ∫ λ S / ∫ S (the response-weighted mean wavelength); FWHM =
// distance between the outermost wavelengths where S reaches half its peak (linearly
// interpolated); equivalent width = ∫ S / max S (the width of a rectangle of the same peak and area).
struct ChannelSummary {
  double centre_nm = 0;
  double fwhm_nm = 0;
  double equivalent_width_nm = 0;
};
ChannelSummary summarise_channel(const DenseSpectrum& weight);

Band make_rgb_band();
// A band from a relative spectral response; `name` must be a valid EXR layer name.
Band make_srf_band(const std::string& name, const DenseSpectrum& response);

// Resolves a band name: "rgb"; "nir" (a silicon camera behind an 850 nm long-pass filter, Basler
// acA2500-20gm, data/srf/helios_camera_nir_srf.csv); "red_edge" (the same camera, 730 nm filter);
// Sentinel-2 "S2A_B2".."S2A_B12" and "S2B_…" (B2–B8A, B11, B12: the bands the shipped table has);
// Landsat OLI "L8_B1".."L8_B9", "L9_…". Throws sylva::Error listing
// the known names otherwise.
Band resolve_band(const std::string& name);
// A user band: column `column` of the table `file` (first column wavelength in nm).
Band load_band(const std::string& name, const std::filesystem::path& file, const std::string& column);

// The names resolve_band accepts, for --help and error messages.
std::vector<std::string> known_band_names();

// Samples the kLambdaCount wavelengths a path carries, for a set of bands (docs/sampling.md,
// "Wavelengths per band"). The bands form at most kLambdaBlocks groups (one per band while there are
// that many; beyond, the bands nearest in centre wavelength share a group), and each group owns
// whole blocks of four lanes: its lanes are stratified in the CDF of its own density p_g ∝ Σ of its
// bands' importance (hero sampling, Wilkie et al. 2014), so adding a band takes no lanes from
// another band's group. Every lane's pdf is the mixture q(λ) = Σ_g (n_g/n) p_g(λ) (n_g of the n
// lanes in group g): the channel estimate Σ_k f(λ_k) w(λ_k) / (n q(λ_k)) is then the multi-sample
// balance heuristic over the groups (Veach 1997, §9.2.2), unbiased for every band, and a band that
// overlaps another's range (S2A_B4 inside rgb) lends it its lanes.
class WavelengthSampler {
 public:
  WavelengthSampler() = default;
  explicit WavelengthSampler(const std::vector<Band>& bands);

  // The lanes from u; the hero lane from u_hero (uniform over the lanes).
  SampledWavelengths sample(float u, float u_hero) const;
  float pdf(float lambda_nm) const;  // q(λ), per nm
  // The group of block b (0 ≤ b < kLambdaBlocks), and the number of groups.
  int group_of_block(int b) const { return block_group_[static_cast<size_t>(b)]; }
  int group_count() const { return static_cast<int>(groups_.size()); }
  // The group of the constructor's band `band`.
  int group_of_band(size_t band) const { return band_group_[band]; }

 private:
  // One group's density, piecewise constant on the 1 nm bins from its first bin with importance to
  // its last, [lo, lo + n) nm: a bin's density per nm is its mass, the difference of the float CDF
  // at its ends (the probability that a uniform u picks it).
  // Inverting the CDF takes one table entry: the cells split [0, 1) into kCells equal parts of u,
  // and each holds the (at most two) bins it overlaps, so a wavelength reads one 16-byte entry and
  // searches nothing (the tables are read after Embree's traversal has evicted them:
  // bench/README.md, "Wavelengths from one table entry"). A cell over three or more bins (bins
  // of less than 1/kCells of the mass each) searches the CDF.
  static constexpr int kCells = 1024;
  struct Cell {
    float cdf0;  // where the bin holding the cell's start begins
    float cdf1;  // where it ends: the start of the next bin with mass (1: none)
    float end1;  // where that next bin ends (1: none): a u beyond lies in a later bin
    uint16_t bin0, bin1;
  };
  static_assert(sizeof(Cell) == 16);
  static_assert(kLambdaSamples <= 65536, "bin indices are 16-bit");
  struct Inversion {
    std::vector<float> cdf;   // n + 1: cdf[i] is the mass of bins [0, i)
    std::vector<Cell> cells;  // kCells
    float lo_nm = kLambdaMin;

    explicit Inversion(std::vector<float> weights);
    float mass(int bin) const { return cdf[static_cast<size_t>(bin) + 1] - cdf[static_cast<size_t>(bin)]; }
    // Four wavelengths at u_k ∈ [0, 1) (one per lane of `uk`).
    glm::vec4 sample4(const float* uk) const;
  };
  int bin_of(float lambda_nm) const { return static_cast<int>(lambda_nm - lo_nm_); }

  std::vector<Inversion> groups_;
  std::vector<int> band_group_;    // per band
  std::vector<int> block_group_;   // kLambdaBlocks
  std::vector<int> block_rank_;    // the block's place among its group's blocks
  std::vector<int> group_blocks_;  // blocks per group
  std::vector<float> pdf_;         // q per 1 nm bin from lo_nm_
  float lo_nm_ = kLambdaMin;
};

}  // namespace sylva
