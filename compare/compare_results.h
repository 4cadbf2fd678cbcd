#pragma once
// Machine-readable results of image comparisons, for CI systems (docs/compare.md, "Results for
// machines"): `sylva compare --json/--junit` and `sylva golden check --json/--junit`.
//
// JSON follows compare/schemas/compare-results.schema.json: one object with the verdict of the
// run and its exit code, and per comparison its verdict ("pass", "fail", "refused", "error"), the
// assumption findings, the per-pixel test, every channel and every local test (region) with its
// statistics. Numbers that are not finite (an exact channel's z) are written as the strings
// "Infinity", "-Infinity" and "NaN".
//
// JUnit XML: <testsuites> with one <testsuite> per comparison, and in it one <testcase> per
// channel and check: "pixels" (the per-pixel test of that channel), then per z-tested channel
// "image", "sky", "class N", "object N", "grid (x,y)" and one "tiles" case for all its tiles;
// a golden case adds "determinism". A failing case holds <failure message="…"> with its z, mean
// shift and place; a refused or unusable comparison one <testcase name="inputs"> with <error>.

#include "compare/assumptions.h"
#include "compare/image_compare.h"

#include <optional>
#include <string>
#include <vector>

namespace sylva {

struct ComparisonRecord {
  std::string name = {};                  // "compare", or the golden case
  std::string test = {}, reference = {};  // what was compared (paths or labels)
  const CompareResult* result = nullptr;  // null when refused or unusable
  AssumptionReport assumptions = {};
  bool refused = false;                          // an assumption check refused the comparison
  std::string error = {};                        // the message when refused or unusable
  std::optional<bool> determinism_matches = {};  // golden: the low-spp hash reproduced (unset: not checked)
  std::string determinism_hash = {};
  double seconds = 0.0;
  // "pass", "fail", "refused" or "error".
  std::string verdict() const;
};

// The exit code of a run over `records` (docs/compare.md): 2 if any comparison was refused or
// unusable, else 1 if any failed, else 0.
int results_exit_code(const std::vector<ComparisonRecord>& records);

std::string results_json(const std::vector<ComparisonRecord>& records, const std::string& command);
std::string results_junit(const std::vector<ComparisonRecord>& records, const std::string& suites_name);

}  // namespace sylva
