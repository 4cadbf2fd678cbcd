#pragma once
// Statistical comparison of a test image against a reference (docs/design.md §8): the engine behind
// `sylva compare` and the golden tests.
//
// Variance convention: for a channel C, "var.C" holds the variance of the pixel *mean* (the
// estimator's variance, σ²/spp), e.g. "var.R", "var.nir.Y". A companion variance file may instead
// hold the plain names ("R", "nir.Y") or the var.* names.
//
// Per-pixel z-test (Mitsuba-style): for each pixel-channel d = test − ref, σ² = Var(d),
//   z = d / σ,  p = erfc(|z| / √2)  (two-sided),
// rejected when p < α_pixel = 1 − (1 − α)^(1/n) (Šidák over the n z-tested pixel-channels).
// Var(d): with both variances and both sample counts (header "sylva:spp") known, the per-sample
// variances are pooled (under H0 both images sample the same distribution; a low-spp test's own
// variance estimate is far too noisy alone: a sky pixel at 16 spp can underestimate it 100×):
//   s² = ((n_t−1)·n_t·var_t + (n_r−1)·n_r·var_r) / (n_t + n_r − 2),  σ² = s²·(1/n_t + 1/n_r).
// With both variances but no spp: σ² = var_ref + var_test. With one side's variance and both spp:
// the other side's is var_known · spp_known / spp_other; without spp it is taken as 0 (an exact
// reference). Zero variance: σ is floored at variance_rel_floor · max(|test|, |ref|), so a
// noiseless pixel must match to ~1e-5 relative (float rounding passes, anything else rejects); two
// exact zeros pass. Identical values always pass (also equal infinities); otherwise a non-finite
// test or reference value rejects.
//
// Mean-bias and variance tests (on by default; compare/regions.h): per channel, D = Σ d over the
// pixels of a region, Var(D) = Σ σ², z_bias = D / √Var(D) (pixels are independent estimates, so D
// is Gaussian by the CLT), and the scatter mean(z²) against 1. They catch small shifts (a +3%
// reflectance change) that no single low-spp pixel can. Regions: the whole image, bias_tile ×
// bias_tile tiles, a coarse bias_grid × bias_grid grid, and per id.class, id.object and the sky
// of the reference; every test of every channel and region is one family, held at bias_alpha by
// Holm's step-down procedure. Pixels that reject on their own are left out of these sums (the
// share counts them), so one firefly cannot fail a tile. Any failing region fails the comparison.
//
// Channel modes: exact_channels must match exactly; channels with an absolute tolerance reject
// when |d| > tol; UInt channels (ids) not listed in either match exactly; the rest are statistical
// (z-test, or the Cycles-style threshold when fail_threshold is set). The z-test verdict uses the
// share of rejecting pixel-channels among all tested ones ≤ max_reject_fraction. The Cycles-style
// fallback matches OpenImageIO idiff as Blender's render tests run it (`idiff -fail T
// -failpercent P`): a pixel fails when any tested channel has |d| > T; the image fails when
// failing pixels > P% of all pixels.

#include "compare/regions.h"
#include "core/image.h"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sylva {

enum class ChannelTest : uint8_t { ZTest, Threshold, Exact, AbsTolerance };

// The test's name as reports and JSON print it ("z-test", "threshold", "exact", "abs-tol").
const char* channel_test_name(ChannelTest test);

struct CompareOptions {
  double alpha = 0.01;                      // family-wise false-rejection rate of the per-pixel z-test
  double max_reject_fraction = 0.0025;      // pass when rejecting pixel-channels / tested ≤ this
  std::vector<std::string> channels;        // empty: all that can be tested (compare_images)
  std::vector<std::string> exact_channels;  // compared exactly (UInt always is)
  std::vector<std::pair<std::string, double>> abs_tolerances;  // channel → absolute tolerance
  double variance_rel_floor = 1e-5;                            // σ ≥ this · max(|test|, |ref|)
  double bias_alpha = 1e-3;              // mean-bias test level (per scale, Šidák); 0 disables it
  int bias_tile = 16;                    // tile size of the local tests; 0: none
  int bias_grid = 4;                     // coarse grid of the local tests, cells per side; 0: none
  int64_t region_min_pixels = 64;        // smallest id.class / id.object / sky region tested
  bool label_regions = true;             // local tests per id.class, id.object and the sky (ids of ref)
  bool variance_test = true;             // per region, also test the scatter (regions.h)
  std::optional<double> fail_threshold;  // Cycles-style fallback: |d| > T fails a pixel ...
  double fail_percent = 0.0;             // ... and > P% failing pixels fail the image (idiff's default 0)
};

struct ChannelReport {
  std::string name;
  ChannelTest test = ChannelTest::ZTest;
  int64_t tested = 0;              // pixel-channels tested
  int64_t rejected = 0;            // pixel-channels rejected
  double mean_rel_diff = 0.0;      // Σ(test − ref) / Σ|ref| (signed; +0.03 for a +3% shift)
  double mean_abs_rel_diff = 0.0;  // Σ|test − ref| / Σ|ref|
  double max_abs_diff = 0.0;
  double bias_z = 0.0;           // whole-image mean-bias z (ZTest channels with the bias test on)
  bool bias_failed = false;      // the whole image fails its bias or variance test
  double tile_z = 0.0;           // the tile mean-bias z of largest magnitude ...
  int tile_x = -1, tile_y = -1;  // ... and its tile's top-left pixel
  bool tile_failed = false;      // some tile fails
  int64_t regions_failed = 0;    // failing regions of this channel, of every kind
  double reject_fraction() const {
    return tested > 0 ? static_cast<double>(rejected) / static_cast<double>(tested) : 0.0;
  }
};

struct WorstPixel {
  int x = -1, y = -1;
  std::string channel;
  double z = 0.0;  // signed z (ZTest), or d / tolerance for the other modes
  double p = 1.0;  // two-sided p-value (ZTest), 0 for a rejecting non-statistical channel
  double test = 0.0, ref = 0.0;
};

struct CompareResult {
  int width = 0, height = 0;
  std::vector<ChannelReport> channels;  // in test order
  std::vector<std::string> skipped;     // channels left out by default (no variance, no tolerance)
  std::string variance_model;           // how the variance of the difference was formed, for the summary
  bool threshold_mode = false;          // Cycles-style fallback used
  int64_t tested = 0, rejected = 0;     // z-test / exact / tolerance pixel-channels
  int64_t failing_pixels = 0;           // threshold mode: pixels with any failing channel
  double reject_fraction = 0.0;         // the figure compared against the limit
  double limit = 0.0;                   // max_reject_fraction, or fail_percent / 100
  double alpha_pixel = 0.0;             // Šidák-corrected per-pixel-channel level
  double z_critical = 0.0;              // |z| above which a pixel-channel rejects
  double bias_z_critical = 0.0;         // Holm's first step: |z| above which the most extreme test fails
  double tile_z_critical = 0.0;         // the same (one family)
  int bias_tile = 0;                    // tile size used (0: no tile test)
  int bias_grid_cell = 0;               // coarse grid cell size used (0: none)
  int64_t family_size = 0;              // tests in the Holm family
  double bias_alpha = 0.0;              // its level
  std::vector<RegionTest> regions;      // every region test, per channel in channel order
  WorstPixel worst;
  bool passed = false;
  // Per tested channel (same order as `channels`): error holds |z| (or |d|/tol, exact: 0/1) plus
  // "reject.Y", 1 where any channel of the pixel rejects; pvalue holds p (1 for non-statistical).
  Image error;
  Image pvalue;
};

// Compares `test` against `ref`. Variances come from var.* channels of the images themselves or
// from the optional companion images (which take precedence). Default channel choice
// (options.channels empty): every channel of ref except var.*, skipping statistical channels
// without any variance unless the threshold fallback is on. Throws sylva::Error for unusable input:
// size mismatch, channels missing from either image, a requested statistical channel without
// variance (and no fallback), a companion of the wrong size.
CompareResult compare_images(const Image& test, const Image& ref, const CompareOptions& options,
                             const Image* test_var = nullptr, const Image* ref_var = nullptr);

// Human-readable summary (verdict, rejecting share, worst pixel, per-channel figures, failing regions).
std::string format_compare_summary(const CompareResult& result);
// The failing regions, most significant first, at most `limit` lines (empty if none fails).
std::string format_failing_regions(const CompareResult& result, size_t limit);

// Two-sided standard-normal p-value and its inverse (|z| with that p).
double two_sided_p(double z);
double two_sided_z(double p);

}  // namespace sylva
