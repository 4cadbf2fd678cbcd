// `sylva golden update|check`: render and review Sylva's golden references (golden/README.md).

#include "app/cli_observer.h"
#include "app/commands.h"
#include "compare/compare_report.h"
#include "compare/golden.h"
#include "core/error.h"

#include <fmt/core.h>

namespace sylva {

namespace {

struct GoldenOptions {
  std::string dir = "golden";
  std::vector<std::string> only;
  GoldenRecord settings;
  std::string report;
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

int run_check(const GoldenOptions& opt) {
  const std::vector<GoldenCase> cases = selected(opt);
  // A check that checked nothing must not pass.
  if (cases.empty()) throw Error("no golden cases in " + (std::filesystem::path(opt.dir) / "scenes").string());
  int failures = 0;
  for (const GoldenCase& c : cases) {
    const GoldenCheck r = check_golden_case(c, {}, {}, {}, opt.overrides);
    const bool ok = r.compare.passed && (r.determinism_matches || !r.determinism_checked);
    failures += !ok;
    fmt::print("{} {}: reject {:.4f}% (limit {:.2f}%), determinism {}\n", ok ? "PASS" : "FAIL", c.name,
               100.0 * r.compare.reject_fraction, 100.0 * r.compare.limit,
               !r.determinism_checked  ? "not checked (--set)"
               : r.determinism_matches ? "ok"
                                       : "CHANGED (" + r.determinism_hash + ")");
    if (!r.compare.passed) fmt::print("{}\n", format_compare_summary(r.compare));
    if (!ok && !opt.report.empty()) {
      ReportOptions ro;
      ro.test_label = c.name + " (check render)";
      ro.ref_label = c.reference.string();
      write_compare_report(std::filesystem::path(opt.report) / c.name, r.test, read_exr(c.reference), r.compare, ro);
      fmt::print("  report: {}\n", (std::filesystem::path(opt.report) / c.name / "index.html").string());
    }
  }
  fmt::print("{} passed, {} failed\n", cases.size() - failures, failures);
  return failures ? 1 : 0;
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
  add_set_option(check, opt->overrides);
  add_set_option(update, opt->overrides);  // refused with a reason: references render the files as they are
  check->callback([mode] { *mode = "check"; });
  return [opt, mode] { return *mode == "update" ? run_update(*opt) : run_check(*opt); };
}

}  // namespace sylva
