// Band-aware wavelengths (WavelengthSampler, core/band.h; docs/sampling.md, "Wavelengths per
// band"): the bands' groups and their blocks of lanes, every channel's balance-heuristic estimate
// unbiased (z-tests), and a band's wavelength noise kept when bands beside it are added.

#include "core/band.h"
#include "core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace sylva {
namespace {

std::vector<Band> bands_of(const std::vector<std::string>& names) {
  std::vector<Band> bands;
  for (const std::string& n : names) bands.push_back(resolve_band(n));
  return bands;
}

struct Moments {
  double mean = 0, variance = 0;
};

// The per-path estimate of ∫ f w dλ, Σ_k f(λ_k) w(λ_k) / (n q(λ_k)) (BandChannels::weigh's form),
// over `paths` paths: its mean and variance.
Moments channel_moments(const WavelengthSampler& s, const DenseSpectrum& w, const DenseSpectrum& f, int paths,
                        uint64_t seed) {
  Pcg32 rng(seed);
  double sum = 0, sum2 = 0;
  for (int p = 0; p < paths; ++p) {
    const SampledWavelengths wl = s.sample(rng.uniform(), rng.uniform());
    double e = 0;
    for (int k = 0; k < kLambdaCount; ++k)
      e += static_cast<double>(f.eval(wl.lambda_nm[k])) * w.eval(wl.lambda_nm[k]) / wl.pdf[k];
    e /= kLambdaCount;
    sum += e;
    sum2 += e * e;
  }
  Moments m;
  m.mean = sum / paths;
  m.variance = std::max(0.0, sum2 / paths - m.mean * m.mean);
  return m;
}

TEST(WavelengthGroups, EachGroupOwnsWholeBlocks) {
  const auto blocks_of = [](const WavelengthSampler& s) {
    std::vector<int> g;
    for (int b = 0; b < kLambdaBlocks; ++b) g.push_back(s.group_of_block(b));
    return g;
  };
  ASSERT_EQ(kLambdaBlocks, 4);
  EXPECT_EQ(blocks_of(WavelengthSampler(bands_of({"rgb"}))), (std::vector<int>{0, 0, 0, 0}));
  EXPECT_EQ(blocks_of(WavelengthSampler(bands_of({"rgb", "nir"}))), (std::vector<int>{0, 0, 1, 1}));
  EXPECT_EQ(blocks_of(WavelengthSampler(bands_of({"rgb", "nir", "S2A_B4"}))), (std::vector<int>{0, 0, 1, 2}));
  // Six bands in four groups: the nearest centres share one (B8 with nir, B4 with rgb).
  const WavelengthSampler six(bands_of({"rgb", "nir", "S2A_B4", "S2A_B8", "S2A_B11", "S2A_B12"}));
  EXPECT_EQ(six.group_count(), 4);
  EXPECT_EQ(six.group_of_band(0), six.group_of_band(2));
  EXPECT_EQ(six.group_of_band(1), six.group_of_band(3));
  EXPECT_NE(six.group_of_band(0), six.group_of_band(1));
  EXPECT_NE(six.group_of_band(4), six.group_of_band(5));
  EXPECT_EQ(blocks_of(six), (std::vector<int>{0, 1, 2, 3}));
}

// Every channel of every band set against ∫ f w dλ on the grid, f the ASTM G173 global spectrum
// (structure from 300 to 2500 nm): |z| < 4.5 (about 7·10⁻⁶ per test of a false alarm).
TEST(WavelengthGroups, EveryChannelIsUnbiased) {
  const DenseSpectrum& f = astm_g173_global();
  const std::vector<std::vector<std::string>> sets = {{"rgb"},
                                                      {"rgb", "nir"},
                                                      {"rgb", "S2A_B4"},
                                                      {"rgb", "nir", "S2A_B4", "S2A_B8"},
                                                      {"rgb", "nir", "S2A_B4", "S2A_B8", "S2A_B11", "S2A_B12"}};
  uint64_t seed = 1;
  for (const auto& names : sets) {
    const std::vector<Band> bands = bands_of(names);
    const WavelengthSampler s(bands);
    for (const Band& band : bands)
      for (size_t c = 0; c < band.channels.size(); ++c) {
        const DenseSpectrum& w = band.weights[c];
        constexpr int kPaths = 20000;
        const Moments m = channel_moments(s, w, f, kPaths, seed++);
        const double exact = f.integral_product(w);
        const double z = (m.mean - exact) / std::sqrt(m.variance / kPaths);
        EXPECT_LT(std::abs(z), 4.5) << band.name << " " << band.channels[c] << " among " << names.size()
                                    << " bands: mean " << m.mean << ", exact " << exact;
      }
  }
}

// rgb keeps a block of its own whatever else is rendered: its R estimate's variance with three
// bands that do not overlap it is that of one block, and with S2A_B4 inside its range (lending its
// lanes through the balance heuristic) no more. Alone, rgb has every block and less noise still.
TEST(WavelengthGroups, AddingBandsKeepsABandsLanes) {
  const DenseSpectrum& f = astm_g173_global();
  const Band rgb = resolve_band("rgb");
  const DenseSpectrum& red = rgb.weights[0];
  constexpr int kPaths = 40000;
  const double alone = channel_moments(WavelengthSampler({rgb}), red, f, kPaths, 11).variance;
  const double apart =
      channel_moments(WavelengthSampler(bands_of({"rgb", "nir", "S2A_B11", "S2A_B12"})), red, f, kPaths, 12).variance;
  const double beside =
      channel_moments(WavelengthSampler(bands_of({"rgb", "nir", "S2A_B4", "S2A_B8"})), red, f, kPaths, 13).variance;
  // Variance estimates from 40 000 paths are good to about 2 %.
  EXPECT_LT(alone, apart);
  EXPECT_LT(beside, 1.1 * apart);
  std::printf("[wavelengths] R variance per path: rgb alone %.4g, one block apart %.4g, beside S2A_B4 %.4g\n", alone,
              apart, beside);
}

}  // namespace
}  // namespace sylva
