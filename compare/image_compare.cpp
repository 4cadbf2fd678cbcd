#include "compare/image_compare.h"

#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sylva {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::optional<double> spp_of(const Image& image) {
  const std::string text = image.attribute("sylva:spp");
  if (text.empty()) return std::nullopt;
  try {
    const double spp = std::stod(text);
    if (spp > 0.0 && std::isfinite(spp)) return spp;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

// A variance plane: which image and channel hold the variance of the mean of one channel.
struct VarianceSource {
  const Image* image = nullptr;
  int channel = -1;
  explicit operator bool() const { return image != nullptr; }
  double at(size_t pixel) const { return image->pixels[pixel * image->channels.size() + static_cast<size_t>(channel)]; }
};

VarianceSource find_variance(const Image& image, const Image* companion, const std::string& channel) {
  if (companion != nullptr) {
    if (int c = companion->find_channel(channel); c >= 0) return {companion, c};
    if (int c = companion->find_channel("var." + channel); c >= 0) return {companion, c};
  }
  if (int c = image.find_channel("var." + channel); c >= 0) return {&image, c};
  return {};
}

}  // namespace

const char* channel_test_name(ChannelTest test) {
  switch (test) {
    case ChannelTest::ZTest:
      return "z-test";
    case ChannelTest::Threshold:
      return "threshold";
    case ChannelTest::Exact:
      return "exact";
    case ChannelTest::AbsTolerance:
      return "abs-tol";
  }
  return "?";
}

namespace {

struct ChannelPlan {
  std::string name;
  ChannelTest test = ChannelTest::ZTest;
  int test_c = -1, ref_c = -1;
  double tolerance = 0.0;  // AbsTolerance / Threshold
  VarianceSource test_var, ref_var;
  double test_var_scale = 0.0;           // estimate var_test as var_ref · this when only ref's is known
  double ref_var_scale = 0.0;            // estimate var_ref as var_test · this when only test's is known
  double spp_test = 0.0, spp_ref = 0.0;  // both > 0: pool the per-sample variances
};

// How the variance of the difference was formed, for the summary: one clause per kind of channel.
struct VarianceKinds {
  bool both = false, pooled = false, ref_only = false, test_only = false, scaled = false;
};

std::string variance_model_text(const VarianceKinds& k, const std::optional<double>& spp_test,
                                const std::optional<double>& spp_ref) {
  std::vector<std::string> models;
  if (k.both)
    models.push_back(k.pooled ? fmt::format("pooled per-sample variance of test ({} spp) and reference ({} spp)",
                                            *spp_test, *spp_ref)
                              : "var_ref + var_test");
  if (k.ref_only)
    models.push_back(k.scaled ? "var_ref · (1 + spp_ref/spp_test)" : "var_ref only (test taken as exact)");
  if (k.test_only)
    models.push_back(k.scaled ? "var_test · (1 + spp_test/spp_ref)" : "var_test only (reference taken as exact)");
  std::string text;
  for (const std::string& m : models) text += (text.empty() ? "" : "; ") + m;
  return text;
}

// The channels to compare: the options' list, or every channel of ref but var.* (which the test
// must have too, and no more), then the exact and tolerance channels named.
std::vector<std::string> channel_names(const Image& test, const Image& ref, const CompareOptions& options) {
  auto is_var = [](const std::string& name) { return name.rfind("var.", 0) == 0; };
  std::vector<std::string> names = options.channels;
  if (names.empty()) {
    std::vector<std::string> only_test, only_ref;
    for (const std::string& c : ref.channels)
      if (!is_var(c)) {
        names.push_back(c);
        if (test.find_channel(c) < 0) only_ref.push_back(c);
      }
    for (const std::string& c : test.channels)
      if (!is_var(c) && ref.find_channel(c) < 0) only_test.push_back(c);
    if (!only_test.empty() || !only_ref.empty()) {
      auto join = [](const std::vector<std::string>& v) {
        std::string s;
        for (const std::string& x : v) s += (s.empty() ? "" : ", ") + printable(x);
        return s.empty() ? std::string("-") : s;
      };
      throw Error(
          fmt::format("channel mismatch: only in test: {}; only in reference: {} (pick channels "
                      "with --channels)",
                      join(only_test), join(only_ref)));
    }
  }
  for (const std::string& c : options.exact_channels)
    if (!contains(names, c)) names.push_back(c);
  for (const auto& [c, tol] : options.abs_tolerances) {
    if (!(tol >= 0.0)) throw Error(fmt::format("tolerance for channel \"{}\" must be >= 0", c));
    if (!contains(names, c)) names.push_back(c);
  }

  return names;
}

// Which channels are compared and how; fills result.skipped and result.variance_model.
std::vector<ChannelPlan> plan_channels(const Image& test, const Image& ref, const CompareOptions& options,
                                       const Image* test_var, const Image* ref_var, CompareResult& result) {
  auto require = [&](const std::string& name) {
    const bool in_test = test.find_channel(name) >= 0, in_ref = ref.find_channel(name) >= 0;
    if (!in_test || !in_ref)
      throw Error(fmt::format("channel \"{}\" is missing from the {}", name,
                              !in_test && !in_ref ? "test and reference images"
                              : !in_test          ? "test image"
                                                  : "reference image"));
  };

  const bool explicit_channels = !options.channels.empty();
  const std::vector<std::string> names = channel_names(test, ref, options);

  const std::optional<double> spp_test = spp_of(test), spp_ref = spp_of(ref);
  std::vector<ChannelPlan> plans;
  VarianceKinds kinds;
  for (const std::string& name : names) {
    require(name);
    ChannelPlan plan;
    plan.name = name;
    plan.test_c = test.find_channel(name);
    plan.ref_c = ref.find_channel(name);
    const auto tol = std::find_if(options.abs_tolerances.begin(), options.abs_tolerances.end(),
                                  [&](const auto& t) { return t.first == name; });
    const bool integer = test.types[static_cast<size_t>(plan.test_c)] == PixelType::UInt ||
                         ref.types[static_cast<size_t>(plan.ref_c)] == PixelType::UInt;
    if (contains(options.exact_channels, name)) {
      plan.test = ChannelTest::Exact;
    } else if (tol != options.abs_tolerances.end()) {
      plan.test = ChannelTest::AbsTolerance;
      plan.tolerance = tol->second;
    } else if (integer) {
      plan.test = ChannelTest::Exact;
    } else if (options.fail_threshold) {
      plan.test = ChannelTest::Threshold;
      plan.tolerance = *options.fail_threshold;
    } else {
      plan.test_var = find_variance(test, test_var, name);
      plan.ref_var = find_variance(ref, ref_var, name);
      if (!plan.test_var && !plan.ref_var) {
        if (explicit_channels)
          throw Error(
              fmt::format("no variance for channel \"{}\": give --ref-var or --test-var (or var.{} layers), "
                          "a tolerance, or the threshold fallback --fail T --fail-percent P",
                          name, name));
        result.skipped.push_back(name);
        continue;
      }
      if (plan.test_var && plan.ref_var) {
        kinds.both = true;
        if (spp_test && spp_ref && *spp_test + *spp_ref > 2.0) {
          kinds.pooled = true;
          plan.spp_test = *spp_test;
          plan.spp_ref = *spp_ref;
        }
      } else if (spp_test && spp_ref) {
        kinds.scaled = true;
        if (plan.ref_var)
          plan.test_var_scale = *spp_ref / *spp_test;
        else
          plan.ref_var_scale = *spp_test / *spp_ref;
      }
      kinds.ref_only = kinds.ref_only || !plan.test_var;
      kinds.test_only = kinds.test_only || !plan.ref_var;
    }
    plans.push_back(std::move(plan));
  }
  if (plans.empty())
    throw Error(
        "no channel can be compared: none has a variance (give --ref-var/--test-var, or use "
        "--fail T --fail-percent P), an exact match or a tolerance");

  result.variance_model += variance_model_text(kinds, spp_test, spp_ref);
  return plans;
}

// Var(test − ref) of one pixel of a z-tested channel (image_compare.h, "Var(d)").
double difference_variance(const ChannelPlan& plan, size_t p) {
  double var = 0.0;
  if (plan.spp_test > 0.0) {
    // Two-sample pooled variance: under H0 both images estimate the same per-sample σ².
    const double nt = plan.spp_test, nr = plan.spp_ref;
    const double s2 =
        ((nt - 1.0) * std::max(0.0, plan.test_var.at(p)) * nt + (nr - 1.0) * std::max(0.0, plan.ref_var.at(p)) * nr) /
        (nt + nr - 2.0);
    return s2 * (1.0 / nt + 1.0 / nr);
  }
  if (plan.ref_var) var += std::max(0.0, plan.ref_var.at(p));
  if (plan.test_var) var += std::max(0.0, plan.test_var.at(p));
  if (plan.test_var_scale > 0.0) var += std::max(0.0, plan.ref_var.at(p)) * plan.test_var_scale;
  if (plan.ref_var_scale > 0.0) var += std::max(0.0, plan.test_var.at(p)) * plan.ref_var_scale;
  return var;
}

// Šidák: the per-test level 1 − (1 − α)^(1/n) keeping the family-wise level at α, without
// cancellation.
double sidak(double alpha, double n) { return n > 0.0 ? -std::expm1(std::log1p(-alpha) / n) : alpha; }

}  // namespace

double two_sided_p(double z) { return std::erfc(std::abs(z) / std::sqrt(2.0)); }

double two_sided_z(double p) {
  if (p >= 1.0) return 0.0;
  if (p <= 0.0) return kInf;
  double lo = 0.0, hi = 40.0;  // erfc(40/√2) underflows; p is never that small in practice
  for (int i = 0; i < 200 && hi - lo > 1e-12; ++i) {
    const double mid = 0.5 * (lo + hi);
    (two_sided_p(mid) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

namespace {

void check_compare_inputs(const Image& test, const Image& ref, const CompareOptions& options, const Image* test_var,
                          const Image* ref_var) {
  if (test.width != ref.width || test.height != ref.height)
    throw Error(fmt::format("size mismatch: test is {}x{}, reference is {}x{}", test.width, test.height, ref.width,
                            ref.height));
  if (test.width <= 0 || test.height <= 0) throw Error("empty images");
  for (const auto& [companion, what] : {std::pair{test_var, "test variance"}, std::pair{ref_var, "reference variance"}})
    if (companion != nullptr && (companion->width != ref.width || companion->height != ref.height))
      throw Error(fmt::format("size mismatch: {} image is {}x{}, reference is {}x{}", what, companion->width,
                              companion->height, ref.width, ref.height));
  if (!(options.alpha > 0.0 && options.alpha < 1.0)) throw Error("alpha must be in (0, 1)");
  if (!(options.max_reject_fraction >= 0.0 && options.max_reject_fraction <= 1.0))
    throw Error("the rejection limit must be in [0, 100%]");
  if (options.fail_threshold && !(*options.fail_threshold >= 0.0)) throw Error("--fail threshold must be >= 0");
}

// One pixel-channel's verdict under its channel's test. `bias_var` is its variance when it enters
// the bias sums (a z-tested, finite pixel that does not reject on its own), else NaN.
struct PixelVerdict {
  double z = 0.0, pval = 1.0, badness = 0.0, error_value = 0.0;
  bool reject = false;
  double bias_var = std::numeric_limits<double>::quiet_NaN();
};

PixelVerdict test_pixel(const ChannelPlan& plan, const CompareOptions& options, const CompareResult& result, double t,
                        double r, size_t p) {
  const double d = t == r ? 0.0 : t - r;  // equal infinities (a miss's depth) match
  const bool finite = std::isfinite(t) && std::isfinite(r);
  const bool identical = t == r;
  PixelVerdict v;
  switch (plan.test) {
    case ChannelTest::ZTest: {
      double var = difference_variance(plan, p);
      const double floor = options.variance_rel_floor * std::max(std::abs(t), std::abs(r));
      if (!std::isfinite(var)) var = kInf;
      var = std::max(var, floor * floor);
      if (identical) {
        v.z = 0.0;
      } else if (!finite) {
        v.z = kInf;
      } else if (var > 0.0) {
        v.z = d / std::sqrt(var);
      } else {
        v.z = d == 0.0 ? 0.0 : kInf;  // two exact zeros
      }
      v.pval = std::isfinite(v.z) ? two_sided_p(v.z) : 0.0;
      v.reject = v.pval < result.alpha_pixel;
      v.badness = std::abs(v.z) / result.z_critical;
      v.error_value = std::abs(v.z);
      // Pixels that reject on their own are counted by the share; leaving them out of the bias
      // sums keeps a single firefly from failing a whole tile or channel.
      if (finite && std::isfinite(var) && !v.reject) v.bias_var = var;
      break;
    }
    case ChannelTest::Threshold:
    case ChannelTest::AbsTolerance:
      v.reject = !identical && (!finite || std::abs(d) > plan.tolerance);
      v.z = identical ? 0.0 : !finite ? kInf : plan.tolerance > 0.0 ? d / plan.tolerance : (d == 0.0 ? 0.0 : kInf);
      v.badness = std::abs(v.z);
      v.error_value = std::abs(v.z);
      v.pval = v.reject ? 0.0 : 1.0;
      break;
    case ChannelTest::Exact:
      v.reject = !identical;
      v.z = v.reject ? kInf : 0.0;
      v.badness = v.reject ? kInf : 0.0;
      v.error_value = v.reject ? 1.0 : 0.0;
      v.pval = v.reject ? 0.0 : 1.0;
      break;
  }
  return v;
}

// Tests every pixel of channel `ci` (plan): writes its error and p-value planes, marks failing
// pixels, keeps the worst pixel (by `worst_badness`) and returns the channel's report.
// `sums` (null: no local tests of this channel) receives the pixels that enter the bias sums.
ChannelReport compare_channel(const ChannelPlan& plan, size_t ci, const Image& test, const Image& ref,
                              const CompareOptions& options, RegionSums* sums, std::vector<uint8_t>& pixel_failed,
                              double& worst_badness, CompareResult& result) {
  ChannelReport report;
  report.name = plan.name;
  report.test = plan.test;
  double sum_d = 0.0, sum_abs_d = 0.0, sum_abs_ref = 0.0;
  const size_t tnc = test.channels.size(), rnc = ref.channels.size();
  const size_t pixel_count = pixel_failed.size();
  for (size_t p = 0; p < pixel_count; ++p) {
    const double t = test.pixels[p * tnc + static_cast<size_t>(plan.test_c)];
    const double r = ref.pixels[p * rnc + static_cast<size_t>(plan.ref_c)];
    const double d = t == r ? 0.0 : t - r;
    const bool finite = std::isfinite(t) && std::isfinite(r);
    const PixelVerdict v = test_pixel(plan, options, result, t, r, p);
    if (sums != nullptr && !std::isnan(v.bias_var)) sums->add(p, d, v.bias_var, r);
    ++report.tested;
    if (v.reject) {
      ++report.rejected;
      pixel_failed[p] = 1;
    }
    if (finite) {
      sum_d += d;
      sum_abs_d += std::abs(d);
      sum_abs_ref += std::abs(r);
      report.max_abs_diff = std::max(report.max_abs_diff, std::abs(d));
    } else if (t != r) {
      report.max_abs_diff = kInf;
    }
    const int x = static_cast<int>(p % static_cast<size_t>(ref.width));
    const int y = static_cast<int>(p / static_cast<size_t>(ref.width));
    result.error.at(x, y, static_cast<int>(ci)) = static_cast<float>(v.error_value);
    result.pvalue.at(x, y, static_cast<int>(ci)) = static_cast<float>(v.pval);
    if (v.badness > worst_badness) {
      worst_badness = v.badness;
      result.worst = WorstPixel{x, y, plan.name, v.z, v.pval, t, r};
    }
  }
  report.mean_rel_diff = sum_abs_ref > 0.0 ? sum_d / sum_abs_ref : (sum_d == 0.0 ? 0.0 : kInf);
  report.mean_abs_rel_diff = sum_abs_ref > 0.0 ? sum_abs_d / sum_abs_ref : (sum_abs_d == 0.0 ? 0.0 : kInf);
  return report;
}

// The local tests' verdicts (Holm over the family) into the channel reports: the whole image's
// bias z, the worst tile, the failing regions.
void judge_regions(const CompareOptions& options, CompareResult& result) {
  result.family_size = holm(result.regions, options.bias_alpha);
  result.bias_alpha = options.bias_alpha;
  result.bias_z_critical =
      two_sided_z(options.bias_alpha / static_cast<double>(std::max<int64_t>(1, result.family_size)));
  result.tile_z_critical = result.bias_z_critical;
  for (ChannelReport& c : result.channels)
    for (const RegionTest& t : result.regions) {
      if (t.channel != c.name) continue;
      c.regions_failed += t.failed() ? 1 : 0;
      if (t.kind == RegionKind::Image) {
        c.bias_z = t.bias_z;
        c.bias_failed = t.failed();
      } else if (t.kind == RegionKind::Tile) {
        c.tile_failed = c.tile_failed || t.failed();
        if (c.tile_x < 0 || std::abs(t.bias_z) > std::abs(c.tile_z)) {
          c.tile_z = t.bias_z;
          c.tile_x = t.x0;
          c.tile_y = t.y0;
        }
      }
    }
}

RegionOptions region_options(const CompareOptions& options) {
  RegionOptions r;
  r.tile = options.bias_tile;
  r.grid = options.bias_grid;
  r.min_pixels = options.region_min_pixels;
  r.labels = options.label_regions;
  r.variance = options.variance_test;
  return r;
}

// The verdict: the share of rejecting pixel-channels (threshold mode: of failing pixels) against
// the limit, and no failing mean-bias test.
void decide(const CompareOptions& options, size_t pixel_count, CompareResult& result) {
  bool bias_failed = false;
  for (const ChannelReport& c : result.channels) bias_failed = bias_failed || c.regions_failed > 0;
  if (result.threshold_mode) {
    // idiff: fail when nfail > failpercent/100 · npels.
    result.limit = options.fail_percent / 100.0;
    result.reject_fraction = static_cast<double>(result.failing_pixels) / static_cast<double>(pixel_count);
    result.passed = static_cast<double>(result.failing_pixels) <= result.limit * static_cast<double>(pixel_count);
  } else {
    result.limit = options.max_reject_fraction;
    result.reject_fraction =
        result.tested > 0 ? static_cast<double>(result.rejected) / static_cast<double>(result.tested) : 0.0;
    result.passed = result.reject_fraction <= result.limit && !bias_failed;
  }
}

}  // namespace

CompareResult compare_images(const Image& test, const Image& ref, const CompareOptions& options, const Image* test_var,
                             const Image* ref_var) {
  check_compare_inputs(test, ref, options, test_var, ref_var);
  CompareResult result;
  result.width = ref.width;
  result.height = ref.height;
  result.threshold_mode = options.fail_threshold.has_value();

  const std::vector<ChannelPlan> plans = plan_channels(test, ref, options, test_var, ref_var, result);

  const size_t pixel_count = static_cast<size_t>(ref.width) * static_cast<size_t>(ref.height);
  int64_t z_channels = 0;
  for (const ChannelPlan& p : plans) z_channels += p.test == ChannelTest::ZTest ? 1 : 0;
  const double n_tests = static_cast<double>(z_channels) * static_cast<double>(pixel_count);
  result.alpha_pixel = sidak(options.alpha, n_tests);
  result.z_critical = two_sided_z(result.alpha_pixel);
  const bool bias_on = options.bias_alpha > 0.0 && options.bias_alpha < 1.0 && !result.threshold_mode && z_channels > 0;
  result.bias_z_critical = kInf;
  result.tile_z_critical = kInf;

  std::vector<std::string> plane_names;
  for (const ChannelPlan& p : plans) plane_names.push_back(p.name);
  result.error = make_image(ref.width, ref.height, plane_names);
  result.error.add_channel("reject.Y", PixelType::Float);
  result.pvalue = make_image(ref.width, ref.height, plane_names);
  const int reject_c = result.error.channel_count() - 1;
  std::vector<uint8_t> pixel_failed(pixel_count, 0);

  const RegionMaps maps = bias_on ? make_region_maps(ref, region_options(options)) : RegionMaps{};
  result.bias_tile = maps.tile;
  result.bias_grid_cell = maps.grid_cell;

  double worst_badness = -1.0;
  for (size_t ci = 0; ci < plans.size(); ++ci) {
    std::optional<RegionSums> sums;
    if (bias_on && plans[ci].test == ChannelTest::ZTest) sums.emplace(maps);
    ChannelReport report = compare_channel(plans[ci], ci, test, ref, options, sums ? &*sums : nullptr, pixel_failed,
                                           worst_badness, result);
    if (sums)
      for (RegionTest& t : sums->finish(plans[ci].name, options.variance_test)) result.regions.push_back(std::move(t));
    result.tested += report.tested;
    result.rejected += report.rejected;
    result.channels.push_back(std::move(report));
  }
  if (bias_on) judge_regions(options, result);
  for (size_t p = 0; p < pixel_count; ++p) {
    result.error.pixels[p * result.error.channels.size() + static_cast<size_t>(reject_c)] = pixel_failed[p];
    result.failing_pixels += pixel_failed[p];
  }
  decide(options, pixel_count, result);
  return result;
}

std::string format_failing_regions(const CompareResult& r, size_t limit) {
  std::vector<const RegionTest*> failing;
  for (const RegionTest& t : r.regions)
    if (t.failed()) failing.push_back(&t);
  if (failing.empty()) return {};
  std::stable_sort(failing.begin(), failing.end(), [](const RegionTest* a, const RegionTest* b) {
    return std::min(a->bias_p_holm, a->variance_p_holm) < std::min(b->bias_p_holm, b->variance_p_holm);
  });
  std::string s = fmt::format("  failing regions ({}):\n", failing.size());
  for (size_t i = 0; i < failing.size() && i < limit; ++i) {
    const RegionTest& t = *failing[i];
    s += fmt::format(
        "    {:<8} {:<18} x {}-{}, y {}-{}, {} px: bias z {:+.2f}{}, mean shift {:+.3g}%, scatter {:.3g}{}\n",
        t.channel, region_name(t), t.x0, t.x1 - 1, t.y0, t.y1 - 1, t.pixels, t.bias_z, t.bias_failed ? "!" : "",
        100.0 * t.mean_shift, t.variance_ratio, t.variance_failed ? "!" : "");
  }
  if (failing.size() > limit) s += fmt::format("    ... and {} more\n", failing.size() - limit);
  return s;
}

std::string format_compare_summary(const CompareResult& r) {
  std::string s;
  bool bias_failed = false, tile_failed = false;
  for (const ChannelReport& c : r.channels) {
    bias_failed = bias_failed || c.bias_failed;
    tile_failed = tile_failed || c.regions_failed > 0;
  }
  s += fmt::format("{}: {}x{}, {}\n", r.passed ? "PASS" : "FAIL", r.width, r.height,
                   r.threshold_mode ? "threshold test (Cycles/idiff style)" : "per-pixel z-test");
  if (r.threshold_mode) {
    s += fmt::format("  failing pixels: {:.4g}% ({} of {}), limit {:.4g}%\n", 100.0 * r.reject_fraction,
                     r.failing_pixels, static_cast<int64_t>(r.width) * r.height, 100.0 * r.limit);
  } else {
    s += fmt::format("  rejecting pixel-channels: {:.4g}% ({} of {}), limit {:.4g}%{}\n", 100.0 * r.reject_fraction,
                     r.rejected, r.tested, 100.0 * r.limit,
                     bias_failed   ? "; mean-bias test FAILED"
                     : tile_failed ? "; local tests FAILED"
                                   : "");
    s += fmt::format("  per pixel-channel: alpha {:.3g} (Sidak), |z| > {:.3f}\n", r.alpha_pixel, r.z_critical);
    if (r.family_size > 0)
      s += fmt::format(
          "  local tests: {} bias and variance tests (image{}{}, labels), Holm at alpha {:.3g}: first |z| > {:.3f}\n",
          r.family_size, r.bias_tile > 0 ? fmt::format(", {0}x{0} tiles", r.bias_tile) : std::string(),
          r.bias_grid_cell > 0 ? fmt::format(", {0}x{0} grid cells", r.bias_grid_cell) : std::string(), r.bias_alpha,
          r.bias_z_critical);
    if (!r.variance_model.empty()) s += fmt::format("  variance of the difference: {}\n", r.variance_model);
  }
  if (r.worst.x >= 0)
    s += fmt::format("  worst: pixel ({}, {}) channel {}: test {:.6g}, ref {:.6g}, {} {:.4g}, p {:.3g}\n", r.worst.x,
                     r.worst.y, r.worst.channel, r.worst.test, r.worst.ref, r.threshold_mode ? "d/T" : "z", r.worst.z,
                     r.worst.p);
  s += fmt::format("  {:<14} {:<9} {:>17} {:>9} {:>14} {:>16} {:>10} {:>22}\n", "channel", "test", "rejected", "share",
                   "mean rel diff", "mean |rel diff|", "bias z", "worst tile z");
  for (const ChannelReport& c : r.channels)
    s += fmt::format("  {:<14} {:<9} {:>17} {:>8.4g}% {:>+13.4g}% {:>15.4g}% {:>10} {:>22}\n", c.name,
                     channel_test_name(c.test), fmt::format("{}/{}", c.rejected, c.tested), 100.0 * c.reject_fraction(),
                     100.0 * c.mean_rel_diff, 100.0 * c.mean_abs_rel_diff,
                     c.test == ChannelTest::ZTest && std::isfinite(r.bias_z_critical)
                         ? fmt::format("{:+.2f}{}", c.bias_z, c.bias_failed ? "!" : "")
                         : std::string("-"),
                     c.tile_x >= 0
                         ? fmt::format("{:+.2f}{} at ({},{})", c.tile_z, c.tile_failed ? "!" : "", c.tile_x, c.tile_y)
                         : std::string("-"));
  s += format_failing_regions(r, 12);
  if (!r.skipped.empty()) {
    std::string list;
    for (const std::string& c : r.skipped) list += (list.empty() ? "" : ", ") + c;
    s += fmt::format("  not compared (no variance; use --abs-tol-channel / --exact-channels): {}\n", list);
  }
  return s;
}

}  // namespace sylva
