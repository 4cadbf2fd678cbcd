// `sylva compare`: statistical comparison of a render against a reference (compare/image_compare.h).

#include "app/commands.h"
#include "compare/assumptions.h"
#include "compare/compare_report.h"
#include "compare/compare_results.h"
#include "compare/image_compare.h"
#include "core/error.h"
#include "core/image.h"

#include <fmt/core.h>

#include <cstdlib>
#include <memory>
#include <optional>

namespace sylva {
namespace {

// "0.25%" → 0.0025; "0.0025" → 0.0025.
double parse_fraction(const std::string& text, const char* option) {
  std::string number = text;
  double scale = 1.0;
  if (!number.empty() && number.back() == '%') {
    number.pop_back();
    scale = 0.01;
  }
  char* end = nullptr;
  const double v = std::strtod(number.c_str(), &end);
  if (number.empty() || end == nullptr || *end != '\0' || !(v >= 0.0))
    throw Error(
        fmt::format("{}: expected a fraction like 0.0025 or a percentage like 0.25%, got \"{}\"", option, text));
  return v * scale;
}

// "Z=0.001" → {"Z", 0.001}.
std::pair<std::string, double> parse_tolerance(const std::string& text) {
  const size_t eq = text.rfind('=');
  char* end = nullptr;
  const std::string value = eq == std::string::npos ? "" : text.substr(eq + 1);
  const double tol = std::strtod(value.c_str(), &end);
  if (eq == std::string::npos || eq == 0 || value.empty() || *end != '\0' || !(tol >= 0.0))
    throw Error(fmt::format("--abs-tol-channel: expected CHANNEL=TOLERANCE (e.g. Z=0.001), got \"{}\"", text));
  return {text.substr(0, eq), tol};
}

struct CompareArgs {
  std::string test, ref, test_var, ref_var, report, json, junit;
  double alpha = 0.01;
  std::string max_reject = "0.25%";
  std::vector<std::string> channels, exact_channels, tolerances;
  double fail = -1.0;  // < 0: no threshold fallback
  double fail_percent = 0.0;
  double bias_alpha = 1e-3;
  int bias_tile = 16;
  int bias_grid = 4;
  int64_t region_min_pixels = 64;
  bool allow_same_seed = false;
  std::vector<std::string> allowed_differences;
  float diff_scale = 16.0f;
  std::string view = "Standard";
  float exposure_ev = 0.0f;
};

CompareOptions compare_options(const CompareArgs& a) {
  CompareOptions options;
  options.alpha = a.alpha;
  options.max_reject_fraction = parse_fraction(a.max_reject, "--max-reject");
  options.channels = a.channels;
  options.exact_channels = a.exact_channels;
  for (const std::string& t : a.tolerances) options.abs_tolerances.push_back(parse_tolerance(t));
  if (a.fail >= 0.0) options.fail_threshold = a.fail;
  options.fail_percent = a.fail_percent;
  options.bias_alpha = a.bias_alpha;
  options.bias_tile = a.bias_tile;
  options.bias_grid = a.bias_grid;
  options.region_min_pixels = a.region_min_pixels;
  return options;
}

// The comparison itself; fills `record` as it goes (its result stays null if the inputs are
// unusable or refused, and the sylva::Error propagates).
void compare_files(const CompareArgs& a, CompareResult& result, ComparisonRecord& record) {
  const CompareOptions options = compare_options(a);
  const Image test = read_exr(a.test);
  const Image ref = read_exr(a.ref);
  std::optional<Image> test_var, ref_var;
  if (!a.test_var.empty()) test_var = read_exr(a.test_var);
  if (!a.ref_var.empty()) ref_var = read_exr(a.ref_var);
  record.assumptions = check_assumptions(test, ref, AssumptionOptions{a.allow_same_seed, a.allowed_differences});
  if (record.assumptions.refused()) {
    record.refused = true;
    throw RefusedComparison("refused: " + record.assumptions.refusal());
  }
  for (const AssumptionFinding& f : record.assumptions.findings) fmt::print("note: {}\n", f.message);
  result = compare_images(test, ref, options, test_var ? &*test_var : nullptr, ref_var ? &*ref_var : nullptr);
  record.result = &result;
  fmt::print("{} vs {}\n{}", a.test, a.ref, format_compare_summary(result));
  if (!a.report.empty()) {
    ReportOptions report;
    report.diff_scale = a.diff_scale;
    report.view = a.view;
    report.exposure_ev = a.exposure_ev;
    report.test_label = a.test;
    report.ref_label = a.ref;
    write_compare_report(a.report, test, ref, result, report);
    fmt::print("report: {}/index.html\n", a.report);
  }
}

int run_compare(const CompareArgs& a, const std::string& command) {
  CompareResult result;
  ComparisonRecord record;
  record.name = "compare";
  record.test = a.test;
  record.reference = a.ref;
  const auto write_results = [&] {
    if (!a.json.empty()) write_text_file(a.json, results_json({record}, command));
    if (!a.junit.empty()) write_text_file(a.junit, results_junit({record}, "sylva compare"));
  };
  try {
    compare_files(a, result, record);
  } catch (const Error& e) {
    record.result = nullptr;
    record.error = e.what();
    write_results();
    throw;
  }
  write_results();
  std::fflush(stdout);
  return results_exit_code({record});
}

}  // namespace

CommandRun add_compare_command(CLI::App& parent) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* cmd = parent.add_subcommand(
      "compare",
      "Compare a render against a reference: per-pixel z-test with the variance of the mean (var.C "
      "layers or a "
      "companion file), Sidak-corrected; exit 0 pass, 1 fail, 2 unusable input");
  cmd->add_option("test", args->test, "Test image (EXR)")->required();
  cmd->add_option("ref", args->ref, "Reference image (EXR)")->required();
  cmd->add_option("--ref-var", args->ref_var, "Reference variance image (channels C or var.C: variance of the mean)");
  cmd->add_option("--test-var", args->test_var, "Test variance image (channels C or var.C)");
  cmd->add_option("--alpha", args->alpha, "Family-wise false-rejection rate of the per-pixel test")
      ->capture_default_str()
      ->check(kFiniteNumber & CLI::Range(1e-12, 0.5));
  cmd->add_option("--max-reject", args->max_reject,
                  "Largest passing share of rejecting pixel-channels (0.25% or 0.0025)")
      ->capture_default_str();
  cmd->add_option("--channels", args->channels, "Channels to compare (default: all but var.*)")->delimiter(',');
  cmd->add_option("--exact-channels", args->exact_channels, "Channels that must match exactly (UInt ids always do)")
      ->delimiter(',');
  cmd->add_option("--abs-tol-channel", args->tolerances, "CHANNEL=TOL: compare with an absolute tolerance (repeatable)")
      ->delimiter(',');
  CLI::Option* fail =
      cmd->add_option("--fail", args->fail,
                      "Threshold fallback without variance (Cycles/idiff): a pixel fails when any channel "
                      "differs by more than T")
          ->check(kFiniteNumber & CLI::NonNegativeNumber);
  cmd->add_option("--fail-percent", args->fail_percent, "... and the image fails when more than P% of pixels fail")
      ->capture_default_str()
      ->needs(fail)
      ->check(kFiniteNumber & CLI::Range(0.0, 100.0));
  cmd->add_option("--bias-alpha", args->bias_alpha,
                  "Family-wise level of the local bias and variance tests (image, tiles, grid, id regions; Holm; 0 "
                  "disables them)")
      ->capture_default_str()
      ->check(kFiniteNumber & CLI::Range(0.0, 0.5));
  cmd->add_option("--bias-tile", args->bias_tile, "Tile size of the local mean-bias test (0: whole image only)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1 << 20));
  cmd->add_option("--bias-grid", args->bias_grid,
                  "Coarse grid of the local tests, cells per side (used when a cell is at least two tiles; 0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1 << 16));
  cmd->add_option("--region-min-pixels", args->region_min_pixels,
                  "Smallest id.class, id.object or sky region given its own local tests")
      ->capture_default_str()
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40));
  cmd->add_flag("--allow-same-seed", args->allow_same_seed,
                "Compare images with the same seed (a determinism check; refused otherwise)");
  cmd->add_option("--allow-difference", args->allowed_differences,
                  "Header differences that are intended: scene, bands, quantity, spectral, depth, sampler, view, "
                  "denoised, or all (refused otherwise)")
      ->delimiter(',');
  cmd->add_option("--json", args->json,
                  "Write the results as JSON (compare/schemas/compare-results.schema.json), also when refused");
  cmd->add_option("--junit", args->junit, "Write the results as JUnit XML: one case per channel and region");
  cmd->add_option("--report", args->report, "Write test/ref/error/pvalue EXRs, PNG previews and index.html here");
  cmd->add_option("--diff-scale", args->diff_scale, "k in the report's |diff| x k previews")
      ->check(kFiniteNumber & CLI::Range(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--exposure", args->exposure_ev, "Exposure of the report's previews in stops")
      ->check(kFiniteNumber & CLI::Range(-64.0, 64.0))
      ->capture_default_str();
  cmd->add_option("--view", args->view, "OCIO view of the report's previews (Standard, ACES, Raw)")
      ->capture_default_str();
  return [args] { return run_compare(*args, fmt::format("sylva compare {} {}", args->test, args->ref)); };
}

}  // namespace sylva
