#pragma once
// Relative mean squared error of an image against a reference: the noise measure of the
// benchmarks (bench/README.md): work = relMSE × CPU-seconds in bench/efficiency.sh (issue 41), and
// the denoiser's equivalent spp in bench/denoise_bench.sh (issue 60). One implementation for both.
//
//   relMSE = mean over the pixels p of rows [row_begin, row_end) and the channels c of
//            e_pc / (r_pc² + ε_c),   e_pc = (x_pc − r_pc)²  [− Var r_pc, the reference's var.<c>,
//                                                            when subtract_reference_variance]
//   ε_c = epsilon_scale · mean_p r_pc²     (RelMseEpsilon::mean_square; issue 41: 10⁻⁴)
//   ε_c = epsilon_scale · (mean_p r_pc)²   (RelMseEpsilon::square_mean; the denoiser's: 10⁻²)
// The means over the rows counted. Errors in double precision. A channel black over every counted
// pixel has ε = 0: its pixels add 0 where the image is black too, else infinity.

#include "core/image.h"

#include <string>
#include <vector>

namespace sylva {

enum class RelMseEpsilon { mean_square, square_mean };

struct RelMseOptions {
  std::vector<std::string> channels = {"R", "G", "B"};
  double epsilon_scale = 1e-4;
  RelMseEpsilon epsilon = RelMseEpsilon::mean_square;
  bool subtract_reference_variance = false;  // needs var.<c> in the reference
  int row_begin = 0, row_end = -1;           // -1: the reference's height
};

// The issue-41 measure: R, G, B, ε = 10⁻⁴ · mean r², no variance subtracted (the defaults above).
inline RelMseOptions issue41_rel_mse() { return {}; }

// Per pixel of the rows counted (row-major, row_begin first): the mean over the channels of the
// relative squared error; relative_mse is their mean. Throws sylva::Error when the sizes differ,
// a channel (or its var.<c>) is missing, or the rows are not inside the reference.
std::vector<double> relative_squared_errors(const Image& test, const Image& ref, const RelMseOptions& options);
double relative_mse(const Image& test, const Image& ref, const RelMseOptions& options = {});

// The reference's beauty channels: those with a var.<C> that are not themselves variances,
// features, albedo or half-buffers (R, G, B, nir.Y, …), in the reference's order.
std::vector<std::string> beauty_channels(const Image& ref);

}  // namespace sylva
