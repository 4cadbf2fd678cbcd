#pragma once
// Golden-image regression testing (docs/design.md §8). A golden case is a scene file
// golden/scenes/<name>.toml with, beside it in golden/:
//   <name>.exr   the reference: mean, variance of the mean (var.*) and AOVs, rendered at high spp
//                by `sylva golden update`; its header records spp, seed, version and scene hash;
//   <name>.toml  the record: reference and check sample counts and seeds, and the hash of a
//                low-spp render that must be reproduced bit for bit (any logic change shows).
// Checking renders the scene at the check spp with another seed and compares it statistically
// with the reference (compare/image_compare.h), and re-renders the determinism image. Every render
// goes through the render call (pipeline/render_call.h): the case loaded once, rendered twice.

#include "compare/assumptions.h"
#include "compare/image_compare.h"
#include "core/image.h"
#include "render/testing/faults.h"
#include "scenes/scene_file.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace sylva {

// Golden renders run Embree's AVX2 kernels whatever the processor has, so a determinism hash
// recorded on one machine holds on every x86-64 machine with AVX2 (EmbreeIsa). Settings' own `isa`
// (a case's scene file) is overridden.
inline constexpr EmbreeIsa kGoldenIsa = EmbreeIsa::kAvx2;

struct GoldenRecord {
  int reference_spp = 4096;
  uint64_t reference_seed = 1;
  int check_spp = 64;
  uint64_t check_seed = 2;
  int determinism_spp = 2;
  uint64_t determinism_seed = 3;
  std::string determinism_hash;  // hex of image_hash() of the determinism render
  std::string scene_hash;
  std::string version;
};

struct GoldenCase {
  std::string name;
  std::filesystem::path scene;      // golden/scenes/<name>.toml
  std::filesystem::path reference;  // golden/<name>.exr
  std::filesystem::path record;     // golden/<name>.toml
};

// The cases under `golden_dir` (one per golden/scenes/*.toml), sorted by name.
std::vector<GoldenCase> list_golden_cases(const std::filesystem::path& golden_dir);

GoldenRecord read_golden_record(const std::filesystem::path& file);                       // throws ParseError
void write_golden_record(const std::filesystem::path& file, const GoldenRecord& record);  // atomic

// Hash of an image's channel names and pixel bits (FNV-1a 64, hex): equal iff bit-identical.
std::string image_hash(const Image& image);

// How golden images are compared: statistical radiance channels (z-test + mean-bias test), ids
// exact, depth and normals within a small absolute tolerance.
CompareOptions golden_compare_options();

// Renders the reference and the determinism image and writes both files of the case.
void update_golden_case(const GoldenCase& c, const GoldenRecord& settings, bool progress);

struct GoldenCheck {
  Image test;  // the check render
  CompareResult compare;
  std::string determinism_hash;  // what this build produced
  bool determinism_matches = false;
  bool determinism_checked = true;  // false with overrides: the scene is not the recorded one
  AssumptionReport assumptions;     // the check render's header against the reference's
};
// `adjust` and `modify` change the settings and the scene before the check renders, and `faults`
// injects transport faults (the power tests use them to show regressions are caught; a plain check
// passes none).
// `overrides` (`--set`) change the case's scene file: the check then shows whether the comparison
// tells that scene from the reference; the scene-hash precondition and the determinism hash are
// not checked (determinism_checked is false).
// The check render's header is checked against the reference's (compare/assumptions.h): the scene
// hash is the record's to check and the sampler may differ (references kept across samplers);
// with `modify` or `overrides` every difference is intended. Any other difference, or a check seed
// equal to the reference's, throws RefusedComparison.
GoldenCheck check_golden_case(const GoldenCase& c, const std::function<void(RenderSettings&)>& adjust = {},
                              const std::function<void(Scene&)>& modify = {}, const TransportFaults& faults = {},
                              const std::vector<std::string>& overrides = {});

}  // namespace sylva
