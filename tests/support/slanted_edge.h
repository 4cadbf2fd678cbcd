#pragma once
// The slanted-edge MTF measurement (ISO 12233 style) of the sensor tests: samples of an edge image,
// each the signed distance of a detector's centre to the edge (in detector pitches) and its value,
// binned at 1/4 pitch into the edge spread function, differenced into the line spread function
// and Fourier transformed at one frequency; the binning's and the difference's own sinc responses
// are divided out. The edge is known (a synthetic edge) or fitted to the image (a rendered one).

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace sylva::test {

struct EdgeSample {
  double distance_pitch = 0;  // signed distance of the detector's centre to the edge
  double value = 0;
};

// The MTF at `f` cycles per pitch along the edge's normal, from samples within 12 pitches of the
// edge. `empty_bins` (if given) receives the number of 1/4-pitch bins no sample fell into: an
// edge not slanted enough leaves gaps.
inline double edge_mtf(const std::vector<EdgeSample>& samples, double f, int* empty_bins = nullptr) {
  constexpr double bin = 0.25, reach = 12.0;
  constexpr int bins = static_cast<int>(2 * reach / bin);
  std::vector<double> sum(bins, 0.0), count(bins, 0.0);
  for (const EdgeSample& s : samples) {
    const int b = static_cast<int>(std::floor((s.distance_pitch + reach) / bin));
    if (b < 0 || b >= bins) continue;
    sum[b] += s.value;
    count[b] += 1;
  }
  std::vector<double> esf(bins);
  int empty = 0;
  for (int b = 0; b < bins; ++b) {
    empty += count[b] == 0;
    esf[b] = sum[b] / std::max(1.0, count[b]);
  }
  if (empty_bins != nullptr) *empty_bins = empty;
  std::complex<double> ft = 0, dc = 0;
  for (int b = 0; b + 1 < bins; ++b) {
    const double lsf = esf[b + 1] - esf[b], x = (b + 1) * bin - reach;
    ft += lsf * std::polar(1.0, -2 * std::numbers::pi * f * x);
    dc += lsf;
  }
  const double sinc = std::sin(std::numbers::pi * f * bin) / (std::numbers::pi * f * bin);
  return std::abs(ft) / std::abs(dc) / (sinc * sinc);
}

// A near-vertical edge x = a + b·y fitted to an image (row-major, `width` × `height` detectors of
// unit pitch, detector (i, j) centred at (i + ½, j + ½)): in each row from `first_row` to
// `last_row` (exclusive) the centroid of the differences along x within 8 pitches of the largest
// one, then a least-squares line through the centroids (ISO 12233's edge location).
struct EdgeLine {
  double a = 0, b = 0;
  // Signed distance of (x, y) to the line, in pitches.
  double distance(double x, double y) const { return (x - a - b * y) / std::sqrt(1 + b * b); }
  // The unit normal's components (u, v) = (1, −b) / √(1 + b²).
  double normal_u() const { return 1 / std::sqrt(1 + b * b); }
  double normal_v() const { return -b / std::sqrt(1 + b * b); }
};

inline EdgeLine fit_edge_line(const std::vector<float>& image, int width, int first_row, int last_row) {
  constexpr int kWindow = 8;  // differences within 8 pitches of the row's largest count
  double sy = 0, sx = 0, syy = 0, sxy = 0, n = 0;
  for (int j = first_row; j < last_row; ++j) {
    const auto difference = [&](int i) {
      return static_cast<double>(image[static_cast<size_t>(j) * width + i + 1]) -
             image[static_cast<size_t>(j) * width + i];
    };
    int peak = 0;
    for (int i = 1; i + 1 < width; ++i)
      if (std::abs(difference(i)) > std::abs(difference(peak))) peak = i;
    double moment = 0, total = 0;
    for (int i = std::max(0, peak - kWindow); i <= std::min(width - 2, peak + kWindow); ++i) {
      moment += (i + 1) * difference(i);
      total += difference(i);
    }
    const double x = moment / total, y = j + 0.5;
    sx += x, sy += y, sxy += x * y, syy += y * y, n += 1;
  }
  EdgeLine line;
  line.b = (n * sxy - sx * sy) / (n * syy - sy * sy);
  line.a = (sx - line.b * sy) / n;
  return line;
}

}  // namespace sylva::test
