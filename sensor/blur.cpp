#include "sensor/blur.h"

#include "core/error.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <numbers>
#include <utility>

namespace sylva {

namespace {

int next_pow2(int n) {
  int p = 1;
  while (p < n) p *= 2;
  return p;
}

// The source index of padded index i (offset `pad` before the plane's first pixel): mirrored about
// both edges (…, 1, 0 | 0, 1, …, n-1 | n-1, n-2, …), with period 2n.
int mirror(int i, int pad, int n) {
  int j = (i - pad) % (2 * n);
  if (j < 0) j += 2 * n;
  return j < n ? j : 2 * n - 1 - j;
}

// A complex grid of nx × ny, row-major.
struct Grid {
  int nx = 0, ny = 0;
  std::vector<double> re, im;
};

// 2-D transform: rows, then columns (each column gathered into a buffer).
void fft_2d(Grid& g, bool inverse) {
  tbb::parallel_for(0, g.ny, [&](int y) {
    fft_radix2(&g.re[static_cast<size_t>(y) * g.nx], &g.im[static_cast<size_t>(y) * g.nx], g.nx, inverse);
  });
  tbb::parallel_for(0, g.nx, [&](int x) {
    std::vector<double> re(static_cast<size_t>(g.ny)), im(static_cast<size_t>(g.ny));
    for (int y = 0; y < g.ny; ++y) {
      re[static_cast<size_t>(y)] = g.re[static_cast<size_t>(y) * g.nx + x];
      im[static_cast<size_t>(y)] = g.im[static_cast<size_t>(y) * g.nx + x];
    }
    fft_radix2(re.data(), im.data(), g.ny, inverse);
    for (int y = 0; y < g.ny; ++y) {
      g.re[static_cast<size_t>(y) * g.nx + x] = re[static_cast<size_t>(y)];
      g.im[static_cast<size_t>(y) * g.nx + x] = im[static_cast<size_t>(y)];
    }
  });
}

// Signed frequency of index k of n, cycles per sample.
double frequency(int k, int n) { return (k <= n / 2 ? k : k - n) / static_cast<double>(n); }

// Filters plane a (real part) and plane b (imaginary part, or none) together: Z = A + iB with
// A(k) = (Z(k) + Z*(-k)) / 2, B(k) = (Z(k) - Z*(-k)) / 2i; Z' = Ha A + i Hb B.
void filter_pair(std::vector<float>* a, std::vector<float>* b, int width, int height, const PlaneOtf& ha,
                 const PlaneOtf& hb, int margin) {
  Grid g;
  g.nx = next_pow2(width + 2 * margin);
  g.ny = next_pow2(height + 2 * margin);
  const size_t n = static_cast<size_t>(g.nx) * g.ny;
  g.re.assign(n, 0.0);
  g.im.assign(n, 0.0);
  const int px = (g.nx - width) / 2, py = (g.ny - height) / 2;
  for (int y = 0; y < g.ny; ++y) {
    const size_t sy = static_cast<size_t>(mirror(y, py, height)) * width;
    for (int x = 0; x < g.nx; ++x) {
      const size_t s = sy + static_cast<size_t>(mirror(x, px, width)), d = static_cast<size_t>(y) * g.nx + x;
      g.re[d] = (*a)[s];
      if (b != nullptr) g.im[d] = (*b)[s];
    }
  }
  fft_2d(g, false);
  Grid out = g;
  tbb::parallel_for(0, g.ny, [&](int ky) {
    const int my = (g.ny - ky) % g.ny;
    const double fy = frequency(ky, g.ny);
    for (int kx = 0; kx < g.nx; ++kx) {
      const int mx = (g.nx - kx) % g.nx;
      const double fx = frequency(kx, g.nx);
      const size_t k = static_cast<size_t>(ky) * g.nx + kx, m = static_cast<size_t>(my) * g.nx + mx;
      const double zr = g.re[k], zi = g.im[k], wr = g.re[m], wi = -g.im[m];  // w = Z*(-k)
      const double ar = (zr + wr) / 2, ai = (zi + wi) / 2;                   // A
      const double br = (zi - wi) / 2, bi = -(zr - wr) / 2;                  // B = (Z - W) / 2i
      const double fa = ha(fx, fy), fb = b != nullptr ? hb(fx, fy) : 0.0;
      out.re[k] = fa * ar - fb * bi;  // Ha A + i Hb B
      out.im[k] = fa * ai + fb * br;
    }
  });
  fft_2d(out, true);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t s = static_cast<size_t>(y + py) * out.nx + static_cast<size_t>(x + px),
                   d = static_cast<size_t>(y) * width + x;
      (*a)[d] = static_cast<float>(out.re[s]);
      if (b != nullptr) (*b)[d] = static_cast<float>(out.im[s]);
    }
}

}  // namespace

void fft_radix2(double* re, double* im, int n, bool inverse) {
  for (int i = 1, j = 0; i < n; ++i) {  // bit reversal
    int bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) {
      std::swap(re[i], re[j]);
      std::swap(im[i], im[j]);
    }
  }
  for (int len = 2; len <= n; len <<= 1) {
    const double angle = (inverse ? 2.0 : -2.0) * std::numbers::pi / len;
    for (int k = 0; k < len / 2; ++k) {
      const double wr = std::cos(angle * k), wi = std::sin(angle * k);
      for (int i = k; i < n; i += len) {
        const int j = i + len / 2;
        const double tr = re[j] * wr - im[j] * wi, ti = re[j] * wi + im[j] * wr;
        re[j] = re[i] - tr;
        im[j] = im[i] - ti;
        re[i] += tr;
        im[i] += ti;
      }
    }
  }
  if (inverse)
    for (int i = 0; i < n; ++i) {
      re[i] /= n;
      im[i] /= n;
    }
}

void filter_planes(std::vector<std::vector<float>>& planes, int width, int height, const std::vector<PlaneOtf>& otfs,
                   int margin_px) {
  if (planes.size() != otfs.size()) throw Error("filter_planes: one OTF per plane expected");
  for (size_t i = 0; i < planes.size(); i += 2) {
    std::vector<float>* b = i + 1 < planes.size() ? &planes[i + 1] : nullptr;
    filter_pair(&planes[i], b, width, height, otfs[i], b != nullptr ? otfs[i + 1] : otfs[i], margin_px);
  }
}

}  // namespace sylva
