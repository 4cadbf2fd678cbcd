#pragma once
// The HTML report of an image comparison (`sylva compare --report DIR`, failing golden tests).
//
// DIR receives, each written atomically:
//   test.exr, ref.exr          the compared images as read (all channels)
//   error.exr                  per tested channel |z| (or |d|/tolerance, exact: 0/1) and "reject.Y"
//   pvalue.exr                 per tested channel the two-sided p-value
//   <item>_test.png, <item>_ref.png, <item>_diff.png, <item>_reject.png
//                              previews per channel group (rgb, nir, albedo, N, Z, ...): test,
//                              reference, |test − ref| × diff_scale, rejecting pixels in red
//   index.html                 verdict, figures, channels and groups with failures listed first
// Creates DIR if needed; throws sylva::Error("path: why") (an unknown view before writing
// anything).

#include "compare/image_compare.h"
#include "core/image.h"

#include <filesystem>
#include <string>

namespace sylva {

struct ReportOptions {
  float diff_scale = 16.0f;       // k in |diff|×k (Blender's render tests use idiff -abs -scale 16)
  std::string view = "Standard";  // OCIO view of the previews (color.h)
  float exposure_ev = 0.0f;       // exposure of the radiometric previews (test, reference, |diff|)
  std::string test_label = "test", ref_label = "reference";  // shown in the HTML (e.g. file paths)
  std::string command;                                       // the command line, shown in the HTML when set
};

void write_compare_report(const std::filesystem::path& dir, const Image& test, const Image& ref,
                          const CompareResult& result, const ReportOptions& options = {});

}  // namespace sylva
