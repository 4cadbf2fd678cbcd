// Machine-readable results (compare/compare_results.h): the JSON validates against
// compare/schemas/compare-results.schema.json and says what the comparison found; the JUnit XML
// (read with pugixml) has one case per channel and region, its failures where the regions fail,
// and counts that add up. The schema validator is shown to reject broken documents too.

#include "compare/compare_results.h"
#include "tests/support/json_parse.h"
#include "tests/support/json_schema.h"

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <fstream>
#include <random>
#include <sstream>

namespace sylva {
namespace compare_results_test {
namespace {

using test::Json;
using test::parse_json;

test::SchemaValidator schema() {
  std::ifstream in(SYLVA_SOURCE_DIR "/compare/schemas/compare-results.schema.json");
  std::stringstream text;
  text << in.rdbuf();
  return test::SchemaValidator(parse_json(text.str()));
}

// 48×48 R,G,B with variance and ids: the left half object 1 (class 1), the right half sky; the
// test's object 1 is `scale` times brighter.
Image labelled(int spp, double scale, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  Image image = make_image(48, 48, {"R", "G", "B", "var.R", "var.G", "var.B"});
  for (const char* id : {"id.instance", "id.object", "id.class"}) image.add_channel(id, PixelType::UInt);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const bool object = x < 24;
      for (int c = 0; c < 3; ++c) {
        const double mu = object ? 0.2 * scale : 0.5, var = std::pow(0.5 * mu, 2) / spp;
        image.at(x, y, c) = static_cast<float>(mu + normal(rng) * std::sqrt(var));
        image.at(x, y, 3 + c) = static_cast<float>(var);
      }
      for (int c = 6; c < 9; ++c) image.at(x, y, c) = object ? 1.0f : 0.0f;
    }
  image.attributes = {{"sylva:spp", std::to_string(spp)}};
  return image;
}

void expect_valid(const std::string& json) {
  const std::vector<std::string> errors = schema().validate(parse_json(json));
  for (const std::string& e : errors) ADD_FAILURE() << e;
}

TEST(CompareResults, JsonValidatesAndSaysWhatFailed) {
  const Image ref = labelled(4096, 1.0, 1);
  const CompareResult pass = compare_images(labelled(64, 1.0, 2), ref, {});
  const CompareResult fail = compare_images(labelled(64, 1.05, 3), ref, {});
  ASSERT_TRUE(pass.passed);
  ASSERT_FALSE(fail.passed);
  ComparisonRecord a{.name = "same", .test = "t.exr", .reference = "r.exr", .result = &pass};
  ComparisonRecord b{.name = "bright", .test = "b.exr", .reference = "r.exr", .result = &fail};
  const std::string json = results_json({a, b}, "sylva compare t.exr r.exr");
  expect_valid(json);
  const Json doc = parse_json(json);
  EXPECT_FALSE(doc["passed"].boolean);
  EXPECT_EQ(doc["exit_code"].number, 1);
  EXPECT_EQ(doc["comparisons"][0]["verdict"].string, "pass");
  const Json& failed = doc["comparisons"][1];
  EXPECT_EQ(failed["verdict"].string, "fail");
  EXPECT_EQ(failed["result"]["regions"].array.size(), fail.regions.size());
  EXPECT_EQ(failed["result"]["local_tests"]["family_size"].number, static_cast<double>(fail.family_size));
  bool object_failed = false;
  for (const Json& r : failed["result"]["regions"].array)
    if (r["kind"].string == "object" && r["label"].number == 1 && r["verdict"].string == "fail") {
      object_failed = true;
      EXPECT_NEAR(r["mean_shift"].number, 0.05, 0.02);
      EXPECT_EQ(r["box"][2].number, 24);
    }
  EXPECT_TRUE(object_failed);
  for (const Json& c : failed["result"]["channels"].array)
    if (c["test"].string == "exact") {
      EXPECT_TRUE(c["bias_z"].is_null());
    }
}

TEST(CompareResults, RefusedAndUnusableAreErrors) {
  ComparisonRecord refused{.name = "seed",
                           .test = "t.exr",
                           .reference = "r.exr",
                           .refused = true,
                           .error = "refused: the test and reference have the same seed (1)"};
  refused.assumptions.findings.push_back({"seed", "sylva:seed", "1", "1", true, "same seed"});
  ComparisonRecord missing{.name = "missing", .test = "t.exr", .reference = "r.exr", .error = "r.exr: no such file"};
  const std::string json = results_json({refused, missing}, "x");
  expect_valid(json);
  const Json doc = parse_json(json);
  EXPECT_EQ(doc["exit_code"].number, 2);
  EXPECT_EQ(doc["comparisons"][0]["verdict"].string, "refused");
  EXPECT_EQ(doc["comparisons"][1]["verdict"].string, "error");
  EXPECT_TRUE(doc["comparisons"][1]["result"].is_null());

  pugi::xml_document xml;
  ASSERT_TRUE(xml.load_string(results_junit({refused, missing}, "suite").c_str()));
  const pugi::xml_node root = xml.child("testsuites");
  EXPECT_EQ(root.attribute("errors").as_int(), 2);
  EXPECT_STREQ(root.child("testsuite").child("testcase").child("error").attribute("type").value(), "refused");
}

TEST(CompareResults, JunitHasACasePerChannelAndRegion) {
  const Image ref = labelled(4096, 1.0, 1);
  const CompareResult fail = compare_images(labelled(64, 1.05, 3), ref, {});
  ComparisonRecord rec{.name = "bright", .test = "b.exr", .reference = "r.exr", .result = &fail};
  rec.determinism_matches = false;
  rec.determinism_hash = "0123";
  pugi::xml_document xml;
  ASSERT_TRUE(xml.load_string(results_junit({rec}, "sylva compare").c_str()));
  const pugi::xml_node root = xml.child("testsuites");
  const pugi::xml_node suite = root.child("testsuite");
  EXPECT_STREQ(suite.attribute("name").value(), "bright");
  int cases = 0, failures = 0;
  std::set<std::string> names;
  for (const pugi::xml_node c : suite.children("testcase")) {
    ++cases;
    failures += c.child("failure") ? 1 : 0;
    names.insert(std::string(c.attribute("classname").value()) + " " + c.attribute("name").value());
  }
  EXPECT_EQ(suite.attribute("tests").as_int(), cases);
  EXPECT_EQ(suite.attribute("failures").as_int(), failures);
  EXPECT_EQ(root.attribute("tests").as_int(), cases);
  // Per z-tested channel: pixels, image, object 1, class 1, sky, tiles; per id channel: pixels; determinism.
  EXPECT_EQ(cases, 3 * 6 + 3 + 1);
  for (const char* name : {"bright.R pixels", "bright.R image", "bright.G object 1", "bright.B class 1", "bright.B sky",
                           "bright.R tiles", "bright.id.class pixels", "bright determinism"})
    EXPECT_TRUE(names.count(name)) << name;
  EXPECT_GE(failures, 4);  // object 1 and class 1 in at least two channels, and determinism
  for (const pugi::xml_node c : suite.children("testcase"))
    if (std::string(c.attribute("name").value()) == "sky") {
      EXPECT_FALSE(c.child("failure")) << c.child("failure").attribute("message").value();
    }
}

TEST(CompareResults, TheValidatorRejectsBrokenDocuments) {
  const Image ref = labelled(4096, 1.0, 1);
  const CompareResult pass = compare_images(labelled(64, 1.0, 2), ref, {});
  ComparisonRecord a{.name = "same", .test = "t.exr", .reference = "r.exr", .result = &pass};
  const std::string good = results_json({a}, "x");
  const auto broken = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    s.replace(at, from.size(), to);
    return schema().validate(parse_json(s));
  };
  EXPECT_FALSE(broken("\"verdict\": \"pass\"", "\"verdict\": \"maybe\"").empty());
  EXPECT_FALSE(broken("\"exit_code\": 0", "\"exit_code\": 7").empty());
  EXPECT_FALSE(broken("\"kind\": \"image\"", "\"kind\": \"planet\"").empty());
  EXPECT_FALSE(broken("\"family_size\": ", "\"family_size\": -1, \"x\": ").empty());
  EXPECT_FALSE(broken("\"bias_z\": ", "\"bias_z\": \"big\", \"y\": ").empty());
  EXPECT_FALSE(broken("\"name\": \"same\", ", "").empty());
}

}  // namespace
}  // namespace compare_results_test
}  // namespace sylva
