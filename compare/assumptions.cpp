#include "compare/assumptions.h"

#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <utility>

namespace sylva {
namespace {

struct Checked {
  const char* key;
  const char* attribute;
};

constexpr Checked kChecked[] = {
    {"scene", "sylva:scene_hash"},       {"bands", "sylva:bands"},
    {"quantity", "sylva:quantity"},      {"spectral", "sylva:irradiance"},
    {"depth", "sylva:max_depth"},        {"sampler", "sylva:sampler"},
    {"view", "sylva:camera_projection"}, {"view", "sylva:camera_intrinsics"},
    {"view", "sylva:world_from_camera"}, {"denoised", "sylva:denoised"},
    {"version", "sylva:version"},
};

bool spectral_attribute(const std::string& name) {
  return name.rfind("sylva:spectral", 0) == 0 || name.rfind("sylva:wavelength", 0) == 0;
}

// Every attribute compared: the fixed list and the spectral ones either image records.
std::vector<std::pair<std::string, std::string>> compared_attributes(const Image& test, const Image& ref) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const Checked& c : kChecked) out.emplace_back(c.key, c.attribute);
  for (const Image* image : {&ref, &test})
    for (const auto& attribute : image->attributes) {
      const std::string& name = attribute.first;
      if (spectral_attribute(name) &&
          std::none_of(out.begin(), out.end(), [&name](const auto& kv) { return kv.second == name; }))
        out.emplace_back("spectral", name);
    }
  return out;
}

// Equal text, or the same text with numbers equal to 1e-5 relative (a band-weighted irradiance
// summed in another order differs in the last printed digit).
bool same_value(const std::string& a, const std::string& b) {
  if (a == b) return true;
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    char* end_a = nullptr;
    char* end_b = nullptr;
    const auto digit = [](const std::string& s, size_t k) {
      return k < s.size() && std::isdigit(static_cast<unsigned char>(s[k])) != 0;
    };
    const bool numeric = digit(a, i) || ((a[i] == '-' || a[i] == '.') && digit(a, i + 1));
    if (numeric) {
      const double x = std::strtod(a.c_str() + i, &end_a), y = std::strtod(b.c_str() + j, &end_b);
      if (end_a == a.c_str() + i || end_b == b.c_str() + j) return false;
      if (std::abs(x - y) > 1e-5 * std::max(std::abs(x), std::abs(y))) return false;
      i = static_cast<size_t>(end_a - a.c_str());
      j = static_cast<size_t>(end_b - b.c_str());
    } else {
      if (a[i] != b[j]) return false;
      ++i;
      ++j;
    }
  }
  return i == a.size() && j == b.size();
}

std::string shorten(const std::string& value) { return value.size() > 60 ? value.substr(0, 57) + "..." : value; }

}  // namespace

const std::vector<std::string>& assumption_keys() {
  static const std::vector<std::string> keys{"seed",  "scene",   "bands", "quantity", "spectral",
                                             "depth", "sampler", "view",  "denoised", "version"};
  return keys;
}

bool AssumptionReport::refused() const {
  return std::any_of(findings.begin(), findings.end(), [](const AssumptionFinding& f) { return f.refused; });
}

std::string AssumptionReport::refusal() const {
  std::string s;
  for (const AssumptionFinding& f : findings)
    if (f.refused) s += (s.empty() ? "" : "; ") + f.message;
  return s;
}

AssumptionReport check_assumptions(const Image& test, const Image& ref, const AssumptionOptions& options) {
  for (const std::string& key : options.allowed)
    if (key != "all" && std::find(assumption_keys().begin(), assumption_keys().end(), key) == assumption_keys().end())
      throw Error(
          fmt::format("unknown difference '{}' (known: seed, scene, bands, quantity, spectral, depth, "
                      "sampler, view, denoised, version, all)",
                      key));
  const auto allowed = [&](const std::string& key) {
    return std::find(options.allowed.begin(), options.allowed.end(), key) != options.allowed.end() ||
           std::find(options.allowed.begin(), options.allowed.end(), "all") != options.allowed.end();
  };
  AssumptionReport report;
  const std::string seed_t = test.attribute("sylva:seed"), seed_r = ref.attribute("sylva:seed");
  if (!seed_t.empty() && seed_t == seed_r) {
    AssumptionFinding f{"seed", "sylva:seed", seed_t, seed_r, !(options.allow_same_seed || allowed("seed")), ""};
    f.message = fmt::format(
        "the test and reference have the same seed ({}): the test is not independent of the reference, so the "
        "statistical test means nothing{}",
        seed_t, f.refused ? " (render another seed, or pass --allow-same-seed for a determinism check)" : "");
    report.findings.push_back(std::move(f));
  }
  for (const auto& [key, attribute] : compared_attributes(test, ref)) {
    const std::string t = test.attribute(attribute), r = ref.attribute(attribute);
    if (same_value(t, r)) continue;
    AssumptionFinding f{key, attribute, t, r, false, ""};
    if (t.empty() || r.empty()) {
      f.message = fmt::format("{} is recorded only in the {} ({}): not compared", attribute,
                              t.empty() ? "reference" : "test", shorten(t.empty() ? r : t));
    } else {
      f.refused = key != "version" && !allowed(key);
      f.message = fmt::format("{} differs: test {}, reference {}{}", attribute, shorten(t), shorten(r),
                              f.refused ? fmt::format(" (pass --allow-difference {} if intended)", key) : "");
    }
    report.findings.push_back(std::move(f));
  }
  return report;
}

}  // namespace sylva
