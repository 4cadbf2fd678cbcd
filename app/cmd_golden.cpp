// `sylva golden update|check`: render and review Sylva's golden references (golden/README.md).

#include "app/cli_observer.h"
#include "app/commands.h"
#include "compare/compare_report.h"
#include "compare/compare_results.h"
#include "compare/golden.h"
#include "core/error.h"

#include <fmt/core.h>

#include <chrono>
#include <deque>

namespace sylva {

namespace {

struct GoldenOptions {
  std::string dir = "golden";
  std::vector<std::string> only;
  GoldenRecord settings;
  std::string report, json, junit;
  std::vector<std::string> overrides;  // --set: every case's scene changed (check only)
  bool quiet = false;
};

std::vector<GoldenCase> selected(const GoldenOptions& opt) {
  std::vector<GoldenCase> cases = list_golden_cases(opt.dir), out;
  for (const GoldenCase& c : cases)
    if (opt.only.empty() || std::find(opt.only.begin(), opt.only.end(), c.name) != opt.only.end()) out.push_back(c);
  for (const std::string& name : opt.only)
    if (std::none_of(cases.begin(), cases.end(), [&](const GoldenCase& c) { return c.name == name; }))
      throw Error("no golden case '" + name + "' in " + opt.dir + "/scenes");
  return out;
}

int run_update(const GoldenOptions& opt) {
  if (!opt.overrides.empty())
    throw Error("golden update renders the cases' scene files as they are; --set is for golden check");
  for (const GoldenCase& c : selected(opt)) {
    if (!opt.quiet) fmt::print(stderr, "golden: rendering {} at {} spp\n", c.name, opt.settings.reference_spp);
    update_golden_case(c, opt.settings, !opt.quiet);
    if (!opt.quiet) fmt::print(stderr, "golden: wrote {} and {}\n", c.reference.string(), c.record.string());
  }
  return 0;
}

// One case: checks it, prints its line (and summary and report when it fails), fills `record`.
void check_case(const GoldenOptions& opt, const GoldenCase& c, std::deque<CompareResult>& results,
                ComparisonRecord& record) {
  const GoldenCheck r = check_golden_case(c, {}, {}, {}, opt.overrides);
  record.assumptions = r.assumptions;
  if (r.determinism_checked) {
    record.determinism_matches = r.determinism_matches;
    record.determinism_hash = r.determinism_hash;
  }
  const bool ok = r.compare.passed && (r.determinism_matches || !r.determinism_checked);
  fmt::print("{} {}: reject {:.4f}% (limit {:.2f}%), determinism {}\n", ok ? "PASS" : "FAIL", c.name,
             100.0 * r.compare.reject_fraction, 100.0 * r.compare.limit,
             !r.determinism_checked  ? "not checked (--set)"
             : r.determinism_matches ? "ok"
                                     : "CHANGED (" + r.determinism_hash + ")");
  for (const AssumptionFinding& f : r.assumptions.findings)  // differences; one-sided attributes are in the JSON
    if (!f.test_value.empty() && !f.ref_value.empty()) fmt::print("  note: {}\n", f.message);
  if (!r.compare.passed) fmt::print("{}\n", format_compare_summary(r.compare));
  if (!ok && !opt.report.empty()) {
    ReportOptions ro;
    ro.test_label = c.name + " (check render)";
    ro.ref_label = c.reference.string();
    write_compare_report(std::filesystem::path(opt.report) / c.name, r.test, read_exr(c.reference), r.compare, ro);
    fmt::print("  report: {}\n", (std::filesystem::path(opt.report) / c.name / "index.html").string());
  }
  CompareResult& kept = results.emplace_back(r.compare);
  kept.error = Image{};  // the records need the statistics, not the planes
  kept.pvalue = Image{};
  record.result = &kept;
}

int run_check(const GoldenOptions& opt) {
  const std::vector<GoldenCase> cases = selected(opt);
  // A check that checked nothing must not pass.
  if (cases.empty()) throw Error("no golden cases in " + (std::filesystem::path(opt.dir) / "scenes").string());
  std::deque<CompareResult> results;
  std::vector<ComparisonRecord> records;
  for (const GoldenCase& c : cases) {
    ComparisonRecord& record = records.emplace_back();
    record.name = c.name;
    record.test = c.scene.string();
    record.reference = c.reference.string();
    const auto start = std::chrono::steady_clock::now();
    try {
      check_case(opt, c, results, record);
    } catch (const Error& e) {
      // A case that cannot be checked (a refusal, a missing reference) is an error, not a pass;
      // the other cases still run.
      record.refused = dynamic_cast<const RefusedComparison*>(&e) != nullptr;
      record.error = e.what();
      fmt::print("ERROR {}: {}\n", c.name, e.what());
    }
    record.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  int passed = 0, errors = 0;
  for (const ComparisonRecord& r : records) {
    passed += r.verdict() == "pass" ? 1 : 0;
    errors += r.result == nullptr ? 1 : 0;
  }
  fmt::print("{} passed, {} failed{}\n", passed, static_cast<int>(records.size()) - passed - errors,
             errors ? fmt::format(", {} could not be checked", errors) : std::string());
  const std::string command = "sylva golden check --dir " + opt.dir;
  if (!opt.json.empty()) write_text_file(opt.json, results_json(records, command));
  if (!opt.junit.empty()) write_text_file(opt.junit, results_junit(records, "sylva golden " + opt.dir));
  return results_exit_code(records);
}

}  // namespace

CommandRun add_golden_command(CLI::App& parent) {
  auto opt = std::make_shared<GoldenOptions>();
  auto mode = std::make_shared<std::string>();
  CLI::App* cmd = parent.add_subcommand("golden", "Render (update) or check Sylva's golden reference images");
  cmd->require_subcommand(1);
  auto common = [&](CLI::App* sub) {
    sub->add_option("--dir", opt->dir, "Golden directory (with scenes/)")->capture_default_str();
    sub->add_option("--only", opt->only, "Only these cases (names of golden/scenes/*.toml)");
  };
  CLI::App* update = cmd->add_subcommand("update", "Render references at high spp and refresh determinism hashes");
  common(update);
  update->add_option("--reference-spp", opt->settings.reference_spp, "Reference samples per pixel")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 24));
  update->add_option("--check-spp", opt->settings.check_spp, "Samples per pixel of the check render")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
  update->add_flag("-q,--quiet", opt->quiet, "No progress");
  update->callback([mode] { *mode = "update"; });
  CLI::App* check = cmd->add_subcommand("check", "Render at low spp and compare with the references");
  common(check);
  check->add_option("--report", opt->report, "Write an HTML report per failing case under this directory");
  check->add_option("--json", opt->json,
                    "Write every case's results as JSON (compare/schemas/compare-results.schema.json)");
  check->add_option("--junit", opt->junit,
                    "Write JUnit XML: a test suite per case, a test case per channel and region");
  add_set_option(check, opt->overrides);
  add_set_option(update, opt->overrides);  // refused with a reason: references render the files as they are
  check->callback([mode] { *mode = "check"; });
  return [opt, mode] { return *mode == "update" ? run_update(*opt) : run_check(*opt); };
}

}  // namespace sylva
