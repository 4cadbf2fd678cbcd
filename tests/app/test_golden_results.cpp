// `sylva golden check --dir` on a user's own folder of cases, and the machine-readable results of
// `sylva compare` and `sylva golden check` (--json validated against the schema, --junit read with
// pugixml), with the documented exit codes: 0 pass, 1 regression, 2 refused or unusable.

#include "tests/support/json_parse.h"
#include "tests/support/json_schema.h"
#include "tests/support/run_command.h"

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>

namespace sylva {
namespace golden_results_test {
namespace {

namespace fs = std::filesystem;
using test::parse_json;
using test::q;
using test::read_text;
using test::run_sylva;

const fs::path kGolden = SYLVA_SOURCE_DIR "/golden";

std::vector<std::string> schema_errors(const fs::path& json) {
  const test::SchemaValidator schema(
      parse_json(read_text(SYLVA_SOURCE_DIR "/compare/schemas/compare-results.schema.json")));
  return schema.validate(parse_json(read_text(json)));
}

// A user's folder: scenes/<name>.toml, <name>.exr and <name>.toml copied from Sylva's case `from`;
// `record_edit` rewrites the record's text.
void add_case(const fs::path& dir, const std::string& name, const std::string& from,
              const std::function<std::string(std::string)>& record_edit = {}) {
  fs::create_directories(dir / "scenes");
  fs::copy_file(kGolden / "scenes" / (from + ".toml"), dir / "scenes" / (name + ".toml"));
  fs::copy_file(kGolden / (from + ".exr"), dir / (name + ".exr"));
  std::string record = read_text(kGolden / (from + ".toml"));
  if (record_edit) record = record_edit(record);
  std::ofstream(dir / (name + ".toml")) << record;
}

TEST(GoldenResults, AUsersFolderWithJsonAndJunit) {
  const fs::path dir = test::fresh_dir("golden_results");
  add_case(dir / "cases", "sunlit", "ground_sun");
  const fs::path json = dir / "r.json", junit = dir / "r.xml";
  const auto ok =
      run_sylva("golden check --dir " + q(dir / "cases") + " --json " + q(json) + " --junit " + q(junit), dir);
  EXPECT_EQ(ok.exit_code, 0) << ok.out << ok.err;
  EXPECT_NE(ok.out.find("PASS sunlit"), std::string::npos) << ok.out;
  for (const std::string& e : schema_errors(json)) ADD_FAILURE() << e;
  const test::Json doc = parse_json(read_text(json));
  EXPECT_EQ(doc["exit_code"].number, 0);
  EXPECT_EQ(doc["comparisons"][0]["name"].string, "sunlit");
  EXPECT_TRUE(doc["comparisons"][0]["determinism"]["matches"].boolean);
  pugi::xml_document xml;
  ASSERT_TRUE(xml.load_file(junit.c_str()));
  EXPECT_EQ(xml.child("testsuites").attribute("failures").as_int(), 0);
  EXPECT_GT(xml.child("testsuites").attribute("tests").as_int(), 10);

  // A record whose check seed is the reference's is refused, the other case still runs: exit 2.
  add_case(dir / "cases", "same_seed", "ground_sky", [](const std::string& r) {
    return std::regex_replace(r, std::regex("check_seed = \\d+"), "check_seed = 1");
  });
  const auto refused = run_sylva("golden check --dir " + q(dir / "cases") + " --json " + q(json), dir);
  EXPECT_EQ(refused.exit_code, 2) << refused.out << refused.err;
  EXPECT_NE(refused.out.find("ERROR same_seed: same_seed: refused: the test and reference have the same seed (1)"),
            std::string::npos)
      << refused.out;
  EXPECT_NE(refused.out.find("PASS sunlit"), std::string::npos) << refused.out;
  for (const std::string& e : schema_errors(json)) ADD_FAILURE() << e;
  const test::Json doc2 = parse_json(read_text(json));
  EXPECT_EQ(doc2["comparisons"][0]["verdict"].string, "refused");
  EXPECT_EQ(doc2["comparisons"][1]["verdict"].string, "pass");

  // A regression (the sun 2 degrees lower through --set): exit 1, the failure in the JUnit file.
  const auto lower = run_sylva(
      "golden check --dir " + q(dir / "cases") + " --only sunlit --set sun.elevation=33" + " --junit " + q(junit), dir);
  EXPECT_EQ(lower.exit_code, 1) << lower.out << lower.err;
  ASSERT_TRUE(xml.load_file(junit.c_str()));
  EXPECT_GT(xml.child("testsuites").attribute("failures").as_int(), 0);
  fs::remove_all(dir);
}

TEST(GoldenResults, CompareWritesJsonAlsoWhenRefused) {
  const fs::path dir = test::fresh_dir("compare_results");
  const fs::path ref = kGolden / "ground_sun.exr", json = dir / "r.json";
  // The reference against itself: the same seed, refused (exit 2), and the JSON says so.
  const auto same = run_sylva("compare " + q(ref) + " " + q(ref) + " --json " + q(json), dir);
  EXPECT_EQ(same.exit_code, 2) << same.out << same.err;
  for (const std::string& e : schema_errors(json)) ADD_FAILURE() << e;
  EXPECT_EQ(parse_json(read_text(json))["comparisons"][0]["verdict"].string, "refused");
  // Allowed for a determinism check: identical images pass.
  const auto allowed = run_sylva("compare " + q(ref) + " " + q(ref) + " --allow-same-seed --json " + q(json), dir);
  EXPECT_EQ(allowed.exit_code, 0) << allowed.out << allowed.err;
  for (const std::string& e : schema_errors(json)) ADD_FAILURE() << e;
  EXPECT_EQ(parse_json(read_text(json))["comparisons"][0]["verdict"].string, "pass");
  // Unusable input: exit 2, verdict "error".
  const auto missing = run_sylva("compare " + q(dir / "nope.exr") + " " + q(ref) + " --json " + q(json), dir);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(parse_json(read_text(json))["comparisons"][0]["verdict"].string, "error");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace golden_results_test
}  // namespace sylva
