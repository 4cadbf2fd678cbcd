#pragma once
// Filtering image planes by an OTF through the FFT (docs/sensors.md, "Optics"). Each plane is
// extended by mirroring to a power-of-two grid with a margin, transformed, multiplied by its own
// real, even OTF and transformed back; two planes share one complex transform. OTF(0, 0) = 1 keeps
// the sum of the extended plane, so a plane dark near its edges keeps its sum (energy).

#include <functional>
#include <vector>

namespace sylva {

// OTF at (fx, fy) cycles per plane pixel, |f| <= 1/2: real and even.
using PlaneOtf = std::function<double(double fx, double fy)>;

// Filters each of `planes` (width × height floats, row-major) by its OTF, in place. `margin_px`:
// the mirrored border added on each side before the transform (at least the PSF's reach).
// Deterministic for any thread count.
void filter_planes(std::vector<std::vector<float>>& planes, int width, int height, const std::vector<PlaneOtf>& otfs,
                   int margin_px);

// In-place radix-2 FFT of `n` (a power of two) complex values `re`, `im` (inverse: scaled by 1/n).
void fft_radix2(double* re, double* im, int n, bool inverse);

}  // namespace sylva
