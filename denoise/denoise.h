#pragma once
// Feature-guided denoising of a rendered still (docs/denoise.md): first-order regression on the
// film's sample-averaged features, candidate filters of several bandwidths, and a per-pixel choice
// among them by two-buffer cross-validation — after Bitterli et al. 2016, "Nonlinearly Weighted
// First-order Regression for Denoising Monte Carlo Renderings" (NFOR), with the deviations
// docs/denoise.md lists.
//
// Plain data in and out; no file I/O here (denoise/denoise_image.h reads the EXR's channels).
// Deterministic: every output pixel is computed by one thread from its inputs alone, so the result
// is bit-identical at any thread count.

#include <cstdint>
#include <vector>

namespace sylva {

// The regression features per pixel, in this order (each a mean over the pixel's samples).
enum DenoiseFeature : int {
  kFeatureAlbedo,   // mean of feature.albedo.<C> over the band channels (sky = 1)
  kFeatureNormalX,  // feature.N.X/Y/Z
  kFeatureNormalY,
  kFeatureNormalZ,
  kFeatureDepth,  // feature.Z, m
  kFeatureSun,    // feature.sun
  kFeatureSky,    // feature.class.sky
  kFeatureLeaf,   // feature.class.leaf
  kDenoiseFeatures
};

// A still's buffers, pixel p = y · width + x, top row first.
struct DenoiseBuffers {
  int width = 0, height = 0;
  int channels = 0;                     // beauty channels of every band group together
  std::vector<float> half[2];           // the even- and odd-sample means, [p · channels + c]
  std::vector<float> variance;          // variance of the whole pixel mean, [p · channels + c]
  std::vector<float> features;          // [p · kDenoiseFeatures + f]
  std::vector<float> feature_variance;  // variance of each feature's mean, same layout (0: unknown)
  std::vector<uint32_t> labels;         // regions never filtered across (id.object); empty: none
};

struct DenoiseSettings {
  int threads = 0;  // 0: all hardware threads
  // The candidates' window radii, increasing (pixels): each gives a zeroth- and a first-order
  // estimate, beside the unfiltered half-buffer.
  std::vector<int> radii{2, 5, 9};
  float color_k = 1.5f;        // the colour weights' bandwidth, in noise standard deviations
  float feature_scale = 2.0f;  // multiplies every feature bandwidth
  float ridge = 0.01f;         // regularisation of the first-order coefficients
  int selection_radius = 3;    // the error estimates are averaged over (2r + 1)² pixels
};

struct DenoiseStats {
  std::vector<uint64_t> chosen;  // pixels per candidate: unfiltered, then (zeroth, first) per radius
  double seconds = 0;
};

// The denoised beauty, [p · channels + c]. Throws sylva::Error on buffers of the wrong sizes.
std::vector<float> denoise(const DenoiseBuffers& buffers, const DenoiseSettings& settings = {},
                           DenoiseStats* stats = nullptr);

}  // namespace sylva
