#pragma once
// What a comparison assumes of its two images, checked against their headers (docs/compare.md,
// "Assumption checks"). A statistical comparison asks whether two independent estimates of the
// same expected image agree; it is meaningless when the test image shares the reference's random
// numbers (the same seed) and answers another question when the two images estimate different
// things (another scene, band list, quantity, spectral setting, integrator depth, view, sampler).
//
// Header attributes read (scenes/scene_file.h annotate_render, scenes/view_metadata.h):
//   seed      sylva:seed                 equal seeds are refused unless allowed (determinism checks)
//   scene     sylva:scene_hash
//   bands     sylva:bands
//   quantity  sylva:quantity
//   spectral  sylva:irradiance and every sylva:spectral* and sylva:wavelength* attribute
//   depth     sylva:max_depth
//   sampler   sylva:sampler               (the sample layout)
//   view      sylva:camera_projection, sylva:camera_intrinsics, sylva:world_from_camera
//   denoised  sylva:denoised              (a denoised image's var.* is not its error)
//   version   sylva:version               reported, never refused
// A difference in any but `version` is refused unless its key (or "all") is allowed. An attribute
// recorded in only one image is reported as not comparable, and not refused (references made
// before the attribute existed lack it).

#include "core/error.h"
#include "core/image.h"

#include <string>
#include <vector>

namespace sylva {

struct AssumptionOptions {
  bool allow_same_seed = false;
  std::vector<std::string> allowed = {};  // keys above whose differences are intended, or "all"
};

struct AssumptionFinding {
  std::string key;                    // seed, scene, bands, ...
  std::string attribute;              // the header attribute
  std::string test_value, ref_value;  // "" where not recorded
  bool refused = false;
  std::string message;  // one line for people
};

struct AssumptionReport {
  std::vector<AssumptionFinding> findings;  // differences, equal seeds, attributes recorded in one image only
  bool refused() const;
  // "the test and reference ... (pass --allow-difference KEY if intended)", one clause per refusal.
  std::string refusal() const;
};

// A comparison refused by the checks (its message starts "refused: " or "<case>: refused: ").
class RefusedComparison : public Error {
 public:
  using Error::Error;
};

// The keys of the list above, for option parsing.
const std::vector<std::string>& assumption_keys();

// Throws sylva::Error for an unknown key in options.allowed.
AssumptionReport check_assumptions(const Image& test, const Image& ref, const AssumptionOptions& options);

}  // namespace sylva
