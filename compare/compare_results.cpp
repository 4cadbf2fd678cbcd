#include "compare/compare_results.h"

#include <fmt/core.h>
#include <pugixml.hpp>

#include <cmath>
#include <sstream>

namespace sylva {
namespace {

std::string json_text(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (u < 0x20) {
      out += fmt::format("\\u{:04x}", u);
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (std::isnan(v)) return "\"NaN\"";
  if (std::isinf(v)) return v > 0 ? "\"Infinity\"" : "\"-Infinity\"";
  return fmt::format("{:.10g}", v);
}

const char* json_bool(bool b) { return b ? "true" : "false"; }

// A channel's own verdict: its share of rejecting pixel-channels against the limit, and its local tests.
bool channel_passed(const CompareResult& r, const ChannelReport& c) {
  return c.reject_fraction() <= r.limit && c.regions_failed == 0;
}

std::string json_assumptions(const AssumptionReport& a) {
  std::string s = "[";
  for (size_t i = 0; i < a.findings.size(); ++i) {
    const AssumptionFinding& f = a.findings[i];
    s += fmt::format(
        "{}{{\"key\": {}, \"attribute\": {}, \"test\": {}, \"reference\": {}, \"refused\": {}, "
        "\"message\": {}}}",
        i ? ", " : "", json_text(f.key), json_text(f.attribute), json_text(f.test_value), json_text(f.ref_value),
        json_bool(f.refused), json_text(f.message));
  }
  return s + "]";
}

std::string json_channel(const CompareResult& r, const ChannelReport& c) {
  const bool z = c.test == ChannelTest::ZTest && r.family_size > 0;
  return fmt::format(
      "{{\"name\": {}, \"test\": \"{}\", \"tested\": {}, \"rejected\": {}, \"reject_fraction\": {}, "
      "\"mean_rel_diff\": {}, \"mean_abs_rel_diff\": {}, \"max_abs_diff\": {}, \"bias_z\": {}, \"worst_tile_z\": {}, "
      "\"regions_failed\": {}, \"verdict\": \"{}\"}}",
      json_text(c.name), channel_test_name(c.test), c.tested, c.rejected, json_number(c.reject_fraction()),
      json_number(c.mean_rel_diff), json_number(c.mean_abs_rel_diff), json_number(c.max_abs_diff),
      z ? json_number(c.bias_z) : "null", z && c.tile_x >= 0 ? json_number(c.tile_z) : "null", c.regions_failed,
      channel_passed(r, c) ? "pass" : "fail");
}

std::string json_region(const RegionTest& t) {
  return fmt::format(
      "{{\"channel\": {}, \"kind\": \"{}\", \"label\": {}, \"name\": {}, \"box\": [{}, {}, {}, {}], \"pixels\": {}, "
      "\"tested\": {}, \"bias_z\": {}, \"bias_p\": {}, \"bias_p_holm\": {}, \"mean_shift\": {}, "
      "\"variance_tested\": {}, \"variance_ratio\": {}, \"variance_z\": {}, \"variance_p\": {}, "
      "\"variance_p_holm\": {}, \"verdict\": \"{}\"}}",
      json_text(t.channel), region_kind_name(t.kind), t.label, json_text(region_name(t)), t.x0, t.y0, t.x1, t.y1,
      t.pixels, t.tested, json_number(t.bias_z), json_number(t.bias_p), json_number(t.bias_p_holm),
      json_number(t.mean_shift), json_bool(t.variance_tested), json_number(t.variance_ratio), json_number(t.variance_z),
      json_number(t.variance_p), json_number(t.variance_p_holm), t.failed() ? "fail" : "pass");
}

std::string json_result(const CompareResult& r) {
  std::string s = fmt::format(
      "{{\"width\": {}, \"height\": {}, \"threshold_mode\": {}, \"passed\": {}, "
      "\"pixel_test\": {{\"tested\": {}, \"rejected\": {}, \"failing_pixels\": {}, \"reject_fraction\": {}, "
      "\"limit\": {}, \"alpha_pixel\": {}, \"z_critical\": {}}}, "
      "\"local_tests\": {{\"alpha\": {}, \"family_size\": {}, \"first_z\": {}, \"tile\": {}, \"grid_cell\": {}, "
      "\"method\": \"holm\"}}, ",
      r.width, r.height, json_bool(r.threshold_mode), json_bool(r.passed), r.tested, r.rejected, r.failing_pixels,
      json_number(r.reject_fraction), json_number(r.limit), json_number(r.alpha_pixel), json_number(r.z_critical),
      json_number(r.bias_alpha), r.family_size, json_number(r.bias_z_critical), r.bias_tile, r.bias_grid_cell);
  s += r.worst.x >= 0 ? fmt::format(
                            "\"worst_pixel\": {{\"x\": {}, \"y\": {}, \"channel\": {}, \"z\": {}, \"p\": {}, "
                            "\"test\": {}, \"reference\": {}}}, ",
                            r.worst.x, r.worst.y, json_text(r.worst.channel), json_number(r.worst.z),
                            json_number(r.worst.p), json_number(r.worst.test), json_number(r.worst.ref))
                      : std::string("\"worst_pixel\": null, ");
  s += "\"skipped\": [";
  for (size_t i = 0; i < r.skipped.size(); ++i) s += (i ? ", " : "") + json_text(r.skipped[i]);
  s += "], \"channels\": [";
  for (size_t i = 0; i < r.channels.size(); ++i) s += (i ? ",\n      " : "\n      ") + json_channel(r, r.channels[i]);
  s += "], \"regions\": [";
  for (size_t i = 0; i < r.regions.size(); ++i) s += (i ? ",\n      " : "\n      ") + json_region(r.regions[i]);
  return s + "]}";
}

}  // namespace

std::string ComparisonRecord::verdict() const {
  if (refused) return "refused";
  if (result == nullptr) return "error";
  const bool determinism_ok = !determinism_matches.has_value() || *determinism_matches;
  return result->passed && determinism_ok ? "pass" : "fail";
}

int results_exit_code(const std::vector<ComparisonRecord>& records) {
  int code = 0;
  for (const ComparisonRecord& r : records) {
    const std::string v = r.verdict();
    if (v == "refused" || v == "error") return 2;
    if (v == "fail") code = 1;
  }
  return code;
}

std::string results_json(const std::vector<ComparisonRecord>& records, const std::string& command) {
  const int exit_code = results_exit_code(records);
  std::string s = fmt::format(
      "{{\n  \"schema\": \"sylva-compare-results/1\",\n  \"tool\": \"sylva {}\",\n  \"command\": {},\n"
      "  \"passed\": {},\n  \"exit_code\": {},\n  \"comparisons\": [",
      SYLVA_VERSION, json_text(command), json_bool(exit_code == 0), exit_code);
  for (size_t i = 0; i < records.size(); ++i) {
    const ComparisonRecord& c = records[i];
    s += fmt::format(
        "{}\n    {{\"name\": {}, \"test\": {}, \"reference\": {}, \"verdict\": \"{}\", \"message\": {}, "
        "\"seconds\": {}, \"assumptions\": {},\n     \"determinism\": {},\n     \"result\": {}}}",
        i ? "," : "", json_text(c.name), json_text(c.test), json_text(c.reference), c.verdict(), json_text(c.error),
        json_number(c.seconds), json_assumptions(c.assumptions),
        c.determinism_matches ? fmt::format("{{\"matches\": {}, \"hash\": {}}}", json_bool(*c.determinism_matches),
                                            json_text(c.determinism_hash))
                              : std::string("null"),
        c.result != nullptr ? json_result(*c.result) : std::string("null"));
  }
  return s + "\n  ]\n}\n";
}

namespace {

struct JunitCounts {
  int tests = 0, failures = 0, errors = 0;
};

pugi::xml_node add_case(pugi::xml_node suite, const std::string& classname, const std::string& name,
                        JunitCounts& counts) {
  pugi::xml_node c = suite.append_child("testcase");
  c.append_attribute("classname") = classname.c_str();
  c.append_attribute("name") = name.c_str();
  c.append_attribute("time") = "0";
  ++counts.tests;
  return c;
}

void add_failure(pugi::xml_node c, const std::string& message, JunitCounts& counts) {
  pugi::xml_node f = c.append_child("failure");
  f.append_attribute("message") = message.c_str();
  f.append_attribute("type") = "regression";
  f.text() = message.c_str();
  ++counts.failures;
}

std::string region_failure(const RegionTest& t) {
  return fmt::format(
      "{} {}: x {}-{}, y {}-{}, {} px: bias z {:+.2f}, mean shift {:+.3g}%, scatter {:.3g} "
      "(Holm p {:.3g}, {:.3g})",
      t.channel, region_name(t), t.x0, t.x1 - 1, t.y0, t.y1 - 1, t.pixels, t.bias_z, 100.0 * t.mean_shift,
      t.variance_ratio, t.bias_p_holm, t.variance_p_holm);
}

// The channel's cases: its pixels, then its regions (tiles as one case).
void junit_channel(pugi::xml_node suite, const std::string& suite_name, const CompareResult& r, const ChannelReport& c,
                   JunitCounts& counts) {
  const std::string classname = suite_name + "." + c.name;
  pugi::xml_node pixels = add_case(suite, classname, "pixels", counts);
  if (c.reject_fraction() > r.limit)
    add_failure(pixels,
                fmt::format("{}: {} of {} pixel-channels reject ({:.4g}%, limit {:.4g}%)", c.name, c.rejected, c.tested,
                            100.0 * c.reject_fraction(), 100.0 * r.limit),
                counts);
  std::string tile_failures;
  int tiles = 0;
  for (const RegionTest& t : r.regions) {
    if (t.channel != c.name) continue;
    if (t.kind == RegionKind::Tile) {
      ++tiles;
      if (t.failed()) tile_failures += (tile_failures.empty() ? "" : "; ") + region_failure(t);
      continue;
    }
    pugi::xml_node rc = add_case(suite, classname, region_name(t), counts);
    if (t.failed()) add_failure(rc, region_failure(t), counts);
  }
  if (tiles > 0) {
    pugi::xml_node tc = add_case(suite, classname, "tiles", counts);
    if (!tile_failures.empty()) add_failure(tc, tile_failures, counts);
  }
}

}  // namespace

std::string results_junit(const std::vector<ComparisonRecord>& records, const std::string& suites_name) {
  pugi::xml_document doc;
  pugi::xml_node decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  pugi::xml_node root = doc.append_child("testsuites");
  root.append_attribute("name") = suites_name.c_str();
  JunitCounts total;
  for (const ComparisonRecord& rec : records) {
    pugi::xml_node suite = root.append_child("testsuite");
    suite.append_attribute("name") = rec.name.c_str();
    pugi::xml_node props = suite.append_child("properties");
    for (const auto& [key, value] : {std::pair<std::string, std::string>{"test", rec.test},
                                     {"reference", rec.reference},
                                     {"verdict", rec.verdict()}}) {
      pugi::xml_node p = props.append_child("property");
      p.append_attribute("name") = key.c_str();
      p.append_attribute("value") = value.c_str();
    }
    JunitCounts counts;
    if (rec.result == nullptr) {
      pugi::xml_node c = add_case(suite, rec.name, "inputs", counts);
      pugi::xml_node e = c.append_child("error");
      e.append_attribute("message") = rec.error.c_str();
      e.append_attribute("type") = rec.refused ? "refused" : "unusable input";
      ++counts.errors;
    } else {
      for (const ChannelReport& c : rec.result->channels) junit_channel(suite, rec.name, *rec.result, c, counts);
    }
    if (rec.determinism_matches) {
      pugi::xml_node c = add_case(suite, rec.name, "determinism", counts);
      if (!*rec.determinism_matches)
        add_failure(c, "the low-spp render changed bits (hash " + rec.determinism_hash + ")", counts);
    }
    suite.append_attribute("tests") = counts.tests;
    suite.append_attribute("failures") = counts.failures;
    suite.append_attribute("errors") = counts.errors;
    suite.append_attribute("time") = fmt::format("{:.3f}", rec.seconds).c_str();
    total.tests += counts.tests;
    total.failures += counts.failures;
    total.errors += counts.errors;
  }
  root.append_attribute("tests") = total.tests;
  root.append_attribute("failures") = total.failures;
  root.append_attribute("errors") = total.errors;
  std::ostringstream out;
  doc.save(out, "  ");
  return out.str();
}

}  // namespace sylva
