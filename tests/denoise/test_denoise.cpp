// The denoiser (denoise/denoise.h) on synthetic buffers with known truth: a constant plus noise
// comes back constant within its error, a step across an id boundary does not bleed, the mean is
// kept, and the result is bit-identical at 1 and 2 threads; and the EXR layer's errors.

#include "core/error.h"
#include "core/rng.h"
#include "denoise/denoise_image.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sylva {
namespace {

constexpr int kW = 48, kH = 32, kC = 3;
constexpr float kSigma = 0.2f;  // noise of one half-buffer's pixel mean

// Buffers whose truth is `truth(x, y, c)`, each half with independent Gaussian noise of standard
// deviation kSigma, the variance of the whole mean kSigma² / 2; flat features (a grey wall).
template <typename Truth>
DenoiseBuffers noisy_buffers(Truth truth, uint64_t seed) {
  DenoiseBuffers b;
  b.width = kW;
  b.height = kH;
  b.channels = kC;
  const size_t pixels = static_cast<size_t>(kW) * kH;
  for (auto& h : b.half) h.resize(pixels * kC);
  b.variance.assign(pixels * kC, kSigma * kSigma / 2);
  b.features.assign(pixels * kDenoiseFeatures, 0.0f);
  b.feature_variance.assign(pixels * kDenoiseFeatures, 0.0f);
  Pcg32 rng(seed);
  const auto gauss = [&rng] {
    const float u1 = std::max(rng.uniform(), 1e-7f), u2 = rng.uniform();
    return std::sqrt(-2.0f * std::log(u1)) * std::cos(6.2831853f * u2);
  };
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const size_t p = static_cast<size_t>(y) * kW + x;
      float* f = &b.features[p * kDenoiseFeatures];
      f[kFeatureAlbedo] = 0.5f;
      f[kFeatureNormalZ] = 1.0f;
      f[kFeatureDepth] = 10.0f;
      f[kFeatureSun] = 1.0f;
      for (int c = 0; c < kC; ++c)
        for (auto& h : b.half) h[p * kC + c] = truth(x, y, c) + kSigma * gauss();
    }
  return b;
}

double mean_of(const std::vector<float>& v) {
  double s = 0;
  for (const float x : v) s += x;
  return s / static_cast<double>(v.size());
}

TEST(Denoise, ConstantPlusNoiseComesBackConstant) {
  const DenoiseBuffers b = noisy_buffers([](int, int, int c) { return 1.0f + 0.5f * c; }, 1);
  const std::vector<float> out = denoise(b);
  double noisy_mse = 0, mse = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    const double truth = 1.0 + 0.5 * static_cast<double>(i % kC);
    const double d = out[i] - truth, n = 0.5 * (b.half[0][i] + b.half[1][i]) - truth;
    mse += d * d;
    noisy_mse += n * n;
  }
  mse /= static_cast<double>(out.size());
  noisy_mse /= static_cast<double>(out.size());
  // The noisy mean's error is kSigma²/2 = 0.02; a constant is what the filters model exactly, so
  // the denoised error falls far below it (the widest window averages 225 pixels).
  EXPECT_NEAR(noisy_mse, kSigma * kSigma / 2, 0.004);
  EXPECT_LT(mse, noisy_mse / 10) << "noisy " << noisy_mse;
}

TEST(Denoise, MeanIsPreserved) {
  const DenoiseBuffers b = noisy_buffers(
      [](int x, int y, int c) { return 0.5f + 0.3f * std::sin(0.2f * x) * std::cos(0.15f * y) + 0.1f * c; }, 2);
  const std::vector<float> out = denoise(b);
  std::vector<float> noisy(out.size());
  for (size_t i = 0; i < out.size(); ++i) noisy[i] = 0.5f * (b.half[0][i] + b.half[1][i]);
  // The noisy image mean's standard error: kSigma / sqrt(2 · pixels · channels) ≈ 0.0036; 4 of them.
  const double se = kSigma / std::sqrt(2.0 * kW * kH * kC);
  EXPECT_NEAR(mean_of(out), mean_of(noisy), 4 * se);
}

TEST(Denoise, StepAcrossAnIdBoundaryDoesNotBleed) {
  // The left half 0.2, the right 2.0, the boundary labelled by id; the features the same on both
  // sides, so only the labels keep them apart.
  const auto truth = [](int x, int, int) { return x < kW / 2 ? 0.2f : 2.0f; };
  DenoiseBuffers b = noisy_buffers(truth, 3);
  b.labels.resize(static_cast<size_t>(kW) * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) b.labels[static_cast<size_t>(y) * kW + x] = x < kW / 2 ? 1 : 2;
  const std::vector<float> out = denoise(b);
  // The columns next to the boundary: their mean over the rows and channels is within 4 standard
  // errors of the truth (a bleed of 10 % of the step would be 0.18 off; the standard error of a
  // column's noisy mean is kSigma / sqrt(2 · kH · kC) = 0.02, and denoised it is smaller).
  for (const int x : {kW / 2 - 2, kW / 2 - 1, kW / 2, kW / 2 + 1}) {
    double sum = 0;
    for (int y = 0; y < kH; ++y)
      for (int c = 0; c < kC; ++c) sum += out[(static_cast<size_t>(y) * kW + x) * kC + c];
    EXPECT_NEAR(sum / (kH * kC), truth(x, 0, 0), 4 * kSigma / std::sqrt(2.0 * kH * kC)) << "column " << x;
  }
}

TEST(Denoise, SameBitsAtOneAndTwoThreads) {
  const DenoiseBuffers b =
      noisy_buffers([](int x, int y, int) { return 0.1f * static_cast<float>((x / 7 + y / 5) % 4); }, 4);
  DenoiseSettings one, two;
  one.threads = 1;
  two.threads = 2;
  EXPECT_EQ(denoise(b, one), denoise(b, two));
}

TEST(DenoiseImage, MissingFeaturesAreNamed) {
  Image plain = make_image(4, 4, {"R", "G", "B", "var.R"});
  try {
    denoise_buffers(plain);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--features"), std::string::npos) << e.what();
  }
  Image halves = make_image(4, 4, {"R", "even.R", "odd.R", "var.R"});
  try {
    denoise_buffers(halves);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("feature.albedo.R"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sylva
