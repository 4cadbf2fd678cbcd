#include "core/rgb_spectrum.h"

#include <algorithm>
#include <array>
#include <vector>

namespace sylva {

namespace {

// Smits 1999, Table 1: the basis spectra over ten equal bins of 380–720 nm.
using Basis = std::array<double, 10>;
constexpr Basis kWhite = {1.0000, 1.0000, 0.9999, 0.9993, 0.9992, 0.9998, 1.0000, 1.0000, 1.0000, 1.0000};
constexpr Basis kCyan = {0.9710, 0.9426, 1.0007, 1.0007, 1.0007, 1.0007, 0.1564, 0.0000, 0.0000, 0.0000};
constexpr Basis kMagenta = {1.0000, 1.0000, 0.9685, 0.2229, 0.0000, 0.0458, 0.8369, 1.0000, 1.0000, 0.9959};
constexpr Basis kYellow = {0.0001, 0.0000, 0.1088, 0.6651, 1.0000, 1.0000, 0.9996, 0.9586, 0.9685, 0.9840};
constexpr Basis kRed = {0.1012, 0.0515, 0.0000, 0.0000, 0.0000, 0.0000, 0.8325, 1.0149, 1.0149, 1.0149};
constexpr Basis kGreen = {0.0000, 0.0000, 0.0273, 0.7937, 1.0000, 0.9418, 0.1719, 0.0000, 0.0000, 0.0025};
constexpr Basis kBlue = {1.0000, 1.0000, 0.8916, 0.3323, 0.0000, 0.0000, 0.0003, 0.0369, 0.0483, 0.0496};

// Smits §3: the smallest component is white; the middle one minus the smallest is the secondary
// colour complementary to the smallest channel (cyan, magenta, yellow for R, G, B); the largest
// minus the middle one is the primary of the largest channel.
constexpr std::array<const Basis*, 3> kPrimary = {&kRed, &kGreen, &kBlue};
constexpr std::array<const Basis*, 3> kComplement = {&kCyan, &kMagenta, &kYellow};

void add(Basis& sum, const Basis& basis, double weight) {
  for (size_t i = 0; i < sum.size(); ++i) sum[i] += weight * basis[i];
}

}  // namespace

DenseSpectrum rgb_to_reflectance(const Vec3& linear_rec709) {
  std::array<double, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = std::clamp(static_cast<double>(linear_rec709[k]), 0.0, 1.0);
  // Channels by value; ties keep R before G before B (any order gives the same sum: the tied
  // difference weighs its basis by 0).
  std::array<int, 3> order = {0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return c[a] < c[b]; });
  const int lo = order[0], mid = order[1], hi = order[2];
  Basis s{};
  add(s, kWhite, c[lo]);
  add(s, *kComplement[lo], c[mid] - c[lo]);
  add(s, *kPrimary[hi], c[hi] - c[mid]);
  std::vector<double> lambda(s.size()), value(s.size());
  constexpr double kBinNm = (720.0 - 380.0) / 10.0;
  for (size_t i = 0; i < s.size(); ++i) {
    lambda[i] = 380.0 + kBinNm * (static_cast<double>(i) + 0.5);
    value[i] = std::clamp(s[i], 0.0, 1.0);
  }
  return DenseSpectrum::from_samples(lambda, value, Extrapolate::Clamp);
}

}  // namespace sylva
