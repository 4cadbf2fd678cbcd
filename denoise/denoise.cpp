#include "denoise/denoise.h"

#include "core/error.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

namespace sylva {

namespace {

constexpr int kP = kDenoiseFeatures + 1;  // the regression's unknowns: intercept, then one per feature
constexpr int kPairs = kP * (kP + 1) / 2;
constexpr int kMaxChannels = 64;

// The features' bandwidths (their units; depth is relative, below): what counts as a different
// surface for the weights, and the unit of the regression's coordinates.
constexpr std::array<float, kDenoiseFeatures> kBandwidth{0.1f, 0.3f, 0.3f, 0.3f, 0.05f, 0.3f, 0.25f, 0.35f};

struct Offset {
  int dx, dy;
};

// What every pixel's filter reads: the half-buffers' 3×3 box means (the colour weights' guides)
// with their variances, and the window's offsets ring by ring.
struct Prepared {
  int width = 0, height = 0, nc = 0;
  std::vector<float> guide[2], guide_var[2];
  std::vector<Offset> offsets;   // by ring (Chebyshev distance), then row-major
  std::vector<size_t> ring_end;  // per candidate radius: offsets in its window
};

// The 3×3 box mean of `in` (nc values per pixel; the window clipped at the border), and with
// `variance` the variance of that mean for independent pixels: Σ v / n².
std::vector<float> box3(const std::vector<float>& in, int w, int h, int nc, bool variance) {
  std::vector<float> out(in.size());
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < nc; ++c) {
        double sum = 0;
        int n = 0;
        for (int yy = std::max(0, y - 1); yy <= std::min(h - 1, y + 1); ++yy)
          for (int xx = std::max(0, x - 1); xx <= std::min(w - 1, x + 1); ++xx, ++n)
            sum += in[(static_cast<size_t>(yy) * w + xx) * nc + c];
        out[(static_cast<size_t>(y) * w + x) * nc + c] = static_cast<float>(variance ? sum / (n * n) : sum / n);
      }
  });
  return out;
}

void check(const DenoiseBuffers& b, const DenoiseSettings& s) {
  const size_t pixels = static_cast<size_t>(std::max(0, b.width)) * static_cast<size_t>(std::max(0, b.height));
  const size_t values = pixels * static_cast<size_t>(std::max(0, b.channels));
  if (pixels == 0 || b.channels < 1 || b.channels > kMaxChannels)
    throw Error(fmt::format("denoise: {}x{} pixels of {} channels (1 to {} channels)", b.width, b.height, b.channels,
                            kMaxChannels));
  if (b.half[0].size() != values || b.half[1].size() != values || b.variance.size() != values ||
      b.features.size() != pixels * kDenoiseFeatures || b.feature_variance.size() != pixels * kDenoiseFeatures ||
      (!b.labels.empty() && b.labels.size() != pixels))
    throw Error("denoise: buffers of the wrong size");
  if (s.radii.empty() || s.radii.front() < 1 || !std::is_sorted(s.radii.begin(), s.radii.end()) ||
      s.radii.back() > 32 || s.selection_radius < 0)
    throw Error("denoise: window radii must increase from 1 to at most 32");
}

Prepared prepare(const DenoiseBuffers& b, const DenoiseSettings& s) {
  Prepared p;
  p.width = b.width;
  p.height = b.height;
  p.nc = b.channels;
  std::vector<float> half_var(b.variance.size());
  for (size_t i = 0; i < half_var.size(); ++i) half_var[i] = 2.0f * b.variance[i];  // a half has n/2 samples
  for (int h = 0; h < 2; ++h) {
    p.guide[h] = box3(b.half[h], b.width, b.height, b.channels, false);
    p.guide_var[h] = box3(half_var, b.width, b.height, b.channels, true);
  }
  for (const int r : s.radii) {
    const int inner = p.ring_end.empty() ? -1 : s.radii[p.ring_end.size() - 1];
    for (int ring = inner + 1; ring <= r; ++ring)
      for (int dy = -ring; dy <= ring; ++dy)
        for (int dx = -ring; dx <= ring; ++dx)
          if (std::max(std::abs(dx), std::abs(dy)) == ring) p.offsets.push_back({dx, dy});
    p.ring_end.push_back(p.offsets.size());
  }
  return p;
}

// The weighted least-squares system of one half-buffer: Σ w x xᵀ (upper triangle) and Σ w x yᵀ.
struct System {
  std::array<float, kPairs> a{};
  std::array<float, kP * kMaxChannels> r{};
};

// Solves (A + ridge) β = r for every channel and writes the intercepts (the estimate at the pixel,
// whose features are the origin) to `first`, and r₀/A₀₀ (the weighted mean) to `zeroth`. The
// first-order estimate falls back to the weighted mean when the system is not positive definite.
void solve(const System& sys, int nc, float ridge, float* zeroth, float* first) {
  double m[kP][kP];
  for (int i = 0, k = 0; i < kP; ++i)
    for (int j = i; j < kP; ++j, ++k) m[i][j] = m[j][i] = sys.a[k];
  const double w = m[0][0];
  for (int c = 0; c < nc; ++c) zeroth[c] = static_cast<float>(sys.r[c * kP] / w);
  for (int i = 1; i < kP; ++i) m[i][i] += ridge * w;
  // Cholesky, L in the lower triangle.
  for (int j = 0; j < kP; ++j) {
    double d = m[j][j];
    for (int k = 0; k < j; ++k) d -= m[j][k] * m[j][k];
    if (!(d > 1e-12 * w)) {
      std::copy_n(zeroth, nc, first);
      return;
    }
    m[j][j] = std::sqrt(d);
    for (int i = j + 1; i < kP; ++i) {
      double s = m[i][j];
      for (int k = 0; k < j; ++k) s -= m[i][k] * m[j][k];
      m[i][j] = s / m[j][j];
    }
  }
  for (int c = 0; c < nc; ++c) {
    double z[kP];
    for (int i = 0; i < kP; ++i) {
      double s = sys.r[c * kP + i];
      for (int k = 0; k < i; ++k) s -= m[i][k] * z[k];
      z[i] = s / m[i][i];
    }
    for (int i = kP - 1; i >= 0; --i) {
      double s = z[i];
      for (int k = i + 1; k < kP; ++k) s -= m[k][i] * z[k];
      z[i] = s / m[i][i];
    }
    first[c] = static_cast<float>(z[0]);
  }
}

// The candidates of pixel (x, y) for both halves: out[h][k] points at the pixel's nc values of
// candidate k (0 the half itself; then per radius its zeroth- and first-order estimates).
void filter_pixel(const DenoiseBuffers& b, const Prepared& p, const DenoiseSettings& s, int x, int y,
                  std::vector<float>* const out[2]) {
  const int nc = p.nc, w = p.width;
  const size_t i = static_cast<size_t>(y) * w + x;
  const float* zi = &b.features[i * kDenoiseFeatures];
  const float* vi = &b.feature_variance[i * kDenoiseFeatures];
  std::array<float, kDenoiseFeatures> sigma;
  for (int f = 0; f < kDenoiseFeatures; ++f) sigma[f] = s.feature_scale * kBandwidth[f];
  sigma[kFeatureDepth] *= std::max(zi[kFeatureDepth], 0.0f) + 1.0f;  // relative to the depth, m
  const float k2 = s.color_k * s.color_k;
  for (int h = 0; h < 2; ++h) std::copy_n(&b.half[h][i * nc], nc, &out[h][0][i * nc]);
  System sys[2];
  size_t o = 0;
  for (size_t radius = 0; radius < p.ring_end.size(); ++radius) {
    for (; o < p.ring_end[radius]; ++o) {
      const int xj = x + p.offsets[o].dx, yj = y + p.offsets[o].dy;
      if (xj < 0 || yj < 0 || xj >= w || yj >= p.height) continue;
      const size_t j = static_cast<size_t>(yj) * w + xj;
      if (!b.labels.empty() && b.labels[j] != b.labels[i]) continue;
      const float* zj = &b.features[j * kDenoiseFeatures];
      const float* vj = &b.feature_variance[j * kDenoiseFeatures];
      float xv[kP];
      xv[0] = 1.0f;
      float feature_distance = 0;
      for (int f = 0; f < kDenoiseFeatures; ++f) {
        const float d = zj[f] - zi[f];
        xv[f + 1] = d / sigma[f];
        feature_distance += d * d / (sigma[f] * sigma[f] + vi[f] + vj[f]);
      }
      const float wf = std::exp(-0.5f * feature_distance);
      if (wf < 1e-4f) continue;
      for (int h = 0; h < 2; ++h) {
        // Rousselle et al. 2012's variance-cancelling distance, between the 3×3 box means.
        const float* gi = &p.guide[h][i * nc];
        const float* gj = &p.guide[h][j * nc];
        const float* si = &p.guide_var[h][i * nc];
        const float* sj = &p.guide_var[h][j * nc];
        float color_distance = 0;
        for (int c = 0; c < nc; ++c) {
          const float d = gi[c] - gj[c];
          color_distance += (d * d - (si[c] + std::min(si[c], sj[c]))) / (1e-20f + k2 * (si[c] + sj[c]));
        }
        const float wgt = wf * std::exp(-std::max(0.0f, color_distance / static_cast<float>(nc)));
        if (wgt < 1e-5f) continue;
        System& sy = sys[h];
        for (int a = 0, k = 0; a < kP; ++a) {
          const float wa = wgt * xv[a];
          for (int c2 = a; c2 < kP; ++c2, ++k) sy.a[k] += wa * xv[c2];
        }
        const float* yv = &b.half[h][j * nc];
        for (int c = 0; c < nc; ++c) {
          const float wy = wgt * yv[c];
          for (int a = 0; a < kP; ++a) sy.r[c * kP + a] += wy * xv[a];
        }
      }
    }
    for (int h = 0; h < 2; ++h)
      solve(sys[h], nc, s.ridge, &out[h][1 + 2 * radius][i * nc], &out[h][2 + 2 * radius][i * nc]);
  }
}

// Per candidate, the cross-validated relative error of both halves, (X̂_a − X_b)² − Var(X_b)
// divided by the pixel's squared value, averaged over the selection window; per pixel the
// candidate with the least.
std::vector<uint8_t> select_candidates(const DenoiseBuffers& b, const Prepared& p, const DenoiseSettings& s,
                                       const std::vector<std::vector<float>> cand[2]) {
  const int w = p.width, h = p.height, nc = p.nc, candidates = static_cast<int>(cand[0].size());
  const size_t pixels = static_cast<size_t>(w) * h;
  std::vector<double> channel_mean(nc, 0.0);
  for (size_t i = 0; i < pixels; ++i)
    for (int c = 0; c < nc; ++c) channel_mean[c] += 0.5 * (b.half[0][i * nc + c] + b.half[1][i * nc + c]);
  for (double& m : channel_mean) m = 1e-2 * (m / static_cast<double>(pixels)) * (m / static_cast<double>(pixels));
  std::vector<float> error(pixels * candidates), row_sum(pixels * candidates);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      for (int k = 0; k < candidates; ++k) {
        double e = 0;
        for (int c = 0; c < nc; ++c) {
          const size_t v = i * nc + c;
          const double g = 0.5 * (p.guide[0][v] + p.guide[1][v]);
          const double norm = g * g + channel_mean[c] + 1e-30;
          const double half_var = 2.0 * b.variance[v];
          for (int a = 0; a < 2; ++a) {
            const double d = cand[a][k][v] - b.half[1 - a][v];
            e += (d * d - half_var) / norm;
          }
        }
        error[i * candidates + k] = static_cast<float>(e);
      }
    }
  });
  const int r = s.selection_radius;
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < candidates; ++k) {
        double sum = 0;
        for (int xx = std::max(0, x - r); xx <= std::min(w - 1, x + r); ++xx)
          sum += error[(static_cast<size_t>(y) * w + xx) * candidates + k];
        row_sum[(static_cast<size_t>(y) * w + x) * candidates + k] = static_cast<float>(sum);
      }
  });
  std::vector<uint8_t> chosen(pixels);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      int best = 0;
      double best_error = 0;
      for (int k = 0; k < candidates; ++k) {
        double sum = 0;
        for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy)
          sum += row_sum[(static_cast<size_t>(yy) * w + x) * candidates + k];
        if (k == 0 || sum < best_error) {
          best = k;
          best_error = sum;
        }
      }
      chosen[static_cast<size_t>(y) * w + x] = static_cast<uint8_t>(best);
    }
  });
  return chosen;
}

}  // namespace

std::vector<float> denoise(const DenoiseBuffers& buffers, const DenoiseSettings& settings, DenoiseStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  check(buffers, settings);
  tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
  std::vector<float> result;
  arena.execute([&] {
    const Prepared p = prepare(buffers, settings);
    const int candidates = 1 + 2 * static_cast<int>(settings.radii.size());
    const size_t values = buffers.half[0].size();
    std::vector<std::vector<float>> cand[2];
    for (auto& c : cand) c.assign(static_cast<size_t>(candidates), std::vector<float>(values));
    tbb::parallel_for(0, p.height, [&](int y) {
      std::vector<float>* const out[2] = {cand[0].data(), cand[1].data()};
      for (int x = 0; x < p.width; ++x) filter_pixel(buffers, p, settings, x, y, out);
    });
    const std::vector<uint8_t> chosen = select_candidates(buffers, p, settings, cand);
    result.resize(values);
    const size_t nc = static_cast<size_t>(p.nc);
    for (size_t i = 0; i < chosen.size(); ++i)
      for (size_t c = 0; c < nc; ++c)
        result[i * nc + c] = 0.5f * (cand[0][chosen[i]][i * nc + c] + cand[1][chosen[i]][i * nc + c]);
    if (stats) {
      stats->chosen.assign(static_cast<size_t>(candidates), 0);
      for (const uint8_t k : chosen) ++stats->chosen[k];
    }
  });
  if (stats) stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace sylva
