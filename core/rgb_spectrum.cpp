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

void add(Basis& sum, const Basis& basis, double weight) {
  for (size_t i = 0; i < sum.size(); ++i) sum[i] += weight * basis[i];
}

}  // namespace

DenseSpectrum rgb_to_reflectance(const Vec3& linear_rec709) {
  const double r = std::clamp(static_cast<double>(linear_rec709.x), 0.0, 1.0);
  const double g = std::clamp(static_cast<double>(linear_rec709.y), 0.0, 1.0);
  const double b = std::clamp(static_cast<double>(linear_rec709.z), 0.0, 1.0);
  // Smits §3: the smallest component is white; of the other two, the smaller is the secondary
  // (the complementary of the smallest) and the rest the primary.
  Basis s{};
  if (r <= g && r <= b) {
    add(s, kWhite, r);
    if (g <= b) {
      add(s, kCyan, g - r);
      add(s, kBlue, b - g);
    } else {
      add(s, kCyan, b - r);
      add(s, kGreen, g - b);
    }
  } else if (g <= r && g <= b) {
    add(s, kWhite, g);
    if (r <= b) {
      add(s, kMagenta, r - g);
      add(s, kBlue, b - r);
    } else {
      add(s, kMagenta, b - g);
      add(s, kRed, r - b);
    }
  } else {
    add(s, kWhite, b);
    if (r <= g) {
      add(s, kYellow, r - b);
      add(s, kGreen, g - r);
    } else {
      add(s, kYellow, g - b);
      add(s, kRed, r - g);
    }
  }
  std::vector<double> lambda(s.size()), value(s.size());
  constexpr double kBinNm = (720.0 - 380.0) / 10.0;
  for (size_t i = 0; i < s.size(); ++i) {
    lambda[i] = 380.0 + kBinNm * (static_cast<double>(i) + 0.5);
    value[i] = std::clamp(s[i], 0.0, 1.0);
  }
  return DenseSpectrum::from_samples(lambda, value, Extrapolate::Clamp);
}

}  // namespace sylva
