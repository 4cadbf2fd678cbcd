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

const char* test_name(ChannelTest test) {
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

// Which channels are compared and how; fills result.skipped and result.variance_model.
std::vector<ChannelPlan> plan_channels(const Image& test, const Image& ref, const CompareOptions& options,
                                       const Image* test_var, const Image* ref_var, CompareResult& result) {
  auto is_var = [](const std::string& name) { return name.rfind("var.", 0) == 0; };
  auto require = [&](const std::string& name) {
    const bool in_test = test.find_channel(name) >= 0, in_ref = ref.find_channel(name) >= 0;
    if (!in_test || !in_ref)
      throw Error(fmt::format("channel \"{}\" is missing from the {}", name,
                              !in_test && !in_ref ? "test and reference images"
                              : !in_test          ? "test image"
                                                  : "reference image"));
  };

  // Which channels, in which mode.
  std::vector<std::string> names = options.channels;
  const bool explicit_channels = !names.empty();
  if (!explicit_channels) {
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

  const std::optional<double> spp_test = spp_of(test), spp_ref = spp_of(ref);
  std::vector<ChannelPlan> plans;
  bool any_both = false, any_pooled = false, any_ref_only = false, any_test_only = false, any_scaled = false;
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
        any_both = true;
        if (spp_test && spp_ref && *spp_test + *spp_ref > 2.0) {
          any_pooled = true;
          plan.spp_test = *spp_test;
          plan.spp_ref = *spp_ref;
        }
      } else if (spp_test && spp_ref) {
        any_scaled = true;
        if (plan.ref_var)
          plan.test_var_scale = *spp_ref / *spp_test;
        else
          plan.ref_var_scale = *spp_test / *spp_ref;
      }
      any_ref_only = any_ref_only || !plan.test_var;
      any_test_only = any_test_only || !plan.ref_var;
    }
    plans.push_back(std::move(plan));
  }
  if (plans.empty())
    throw Error(
        "no channel can be compared: none has a variance (give --ref-var/--test-var, or use "
        "--fail T --fail-percent P), an exact match or a tolerance");

  std::vector<std::string> models;
  if (any_both)
    models.push_back(any_pooled ? fmt::format("pooled per-sample variance of test ({} spp) and reference ({} spp)",
                                              *spp_test, *spp_ref)
                                : "var_ref + var_test");
  if (any_ref_only)
    models.push_back(any_scaled ? "var_ref · (1 + spp_ref/spp_test)" : "var_ref only (test taken as exact)");
  if (any_test_only)
    models.push_back(any_scaled ? "var_test · (1 + spp_test/spp_ref)" : "var_test only (reference taken as exact)");
  for (const std::string& m : models) result.variance_model += (result.variance_model.empty() ? "" : "; ") + m;
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

CompareResult compare_images(const Image& test, const Image& ref, const CompareOptions& options, const Image* test_var,
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
  result.bias_z_critical = bias_on ? two_sided_z(sidak(options.bias_alpha, static_cast<double>(z_channels))) : kInf;

  std::vector<std::string> plane_names;
  for (const ChannelPlan& p : plans) plane_names.push_back(p.name);
  result.error = make_image(ref.width, ref.height, plane_names);
  result.error.add_channel("reject.Y", PixelType::Float);
  result.pvalue = make_image(ref.width, ref.height, plane_names);
  const int reject_c = result.error.channel_count() - 1;
  std::vector<uint8_t> pixel_failed(pixel_count, 0);

  // Tiles of the mean-bias test: tile × tile pixels, partial at the right and bottom edges.
  const int tile_size = options.bias_tile > 0 ? options.bias_tile : std::max(ref.width, ref.height);
  const size_t tiles_x = static_cast<size_t>((ref.width + tile_size - 1) / tile_size);
  const size_t tiles_y = static_cast<size_t>((ref.height + tile_size - 1) / tile_size);
  const bool tiles_on = bias_on && options.bias_tile > 0 && tiles_x * tiles_y > 1;
  auto tile_index = [&](size_t p) {
    const size_t x = p % static_cast<size_t>(ref.width), y = p / static_cast<size_t>(ref.width);
    return (y / static_cast<size_t>(tile_size)) * tiles_x + x / static_cast<size_t>(tile_size);
  };
  std::vector<double> tile_sum_d(tiles_x * tiles_y), tile_sum_var(tiles_x * tiles_y);
  result.tile_z_critical =
      tiles_on ? two_sided_z(sidak(options.bias_alpha,
                                   static_cast<double>(static_cast<size_t>(z_channels) * tiles_x * tiles_y)))
               : kInf;
  result.bias_tile = tiles_on ? tile_size : 0;

  double worst_badness = -1.0;
  const size_t tnc = test.channels.size(), rnc = ref.channels.size();
  for (size_t ci = 0; ci < plans.size(); ++ci) {
    const ChannelPlan& plan = plans[ci];
    ChannelReport report;
    report.name = plan.name;
    report.test = plan.test;
    double sum_d = 0.0, sum_abs_d = 0.0, sum_abs_ref = 0.0, sum_var = 0.0, bias_sum_d = 0.0;
    std::fill(tile_sum_d.begin(), tile_sum_d.end(), 0.0);
    std::fill(tile_sum_var.begin(), tile_sum_var.end(), 0.0);
    for (size_t p = 0; p < pixel_count; ++p) {
      const double t = test.pixels[p * tnc + static_cast<size_t>(plan.test_c)];
      const double r = ref.pixels[p * rnc + static_cast<size_t>(plan.ref_c)];
      const double d = t == r ? 0.0 : t - r;  // equal infinities (a miss's depth) match
      const bool finite = std::isfinite(t) && std::isfinite(r);
      const bool identical = t == r;
      double z = 0.0, pval = 1.0, badness = 0.0, error_value = 0.0;
      bool reject = false;
      switch (plan.test) {
        case ChannelTest::ZTest: {
          double var = difference_variance(plan, p);
          const double floor = options.variance_rel_floor * std::max(std::abs(t), std::abs(r));
          if (!std::isfinite(var)) var = kInf;
          var = std::max(var, floor * floor);
          if (identical) {
            z = 0.0;
          } else if (!finite) {
            z = kInf;
          } else if (var > 0.0) {
            z = d / std::sqrt(var);
          } else {
            z = d == 0.0 ? 0.0 : kInf;  // two exact zeros
          }
          pval = std::isfinite(z) ? two_sided_p(z) : 0.0;
          reject = pval < result.alpha_pixel;
          badness = std::abs(z) / result.z_critical;
          error_value = std::abs(z);
          // Pixels that reject on their own are counted by the share; leaving them out of the bias
          // sums keeps a single firefly from failing a whole tile or channel.
          if (finite && std::isfinite(var) && !reject) {
            bias_sum_d += d;
            sum_var += var;
            const size_t tile = tile_index(p);
            tile_sum_d[tile] += d;
            tile_sum_var[tile] += var;
          }
          break;
        }
        case ChannelTest::Threshold:
        case ChannelTest::AbsTolerance:
          reject = !identical && (!finite || std::abs(d) > plan.tolerance);
          z = identical ? 0.0 : !finite ? kInf : plan.tolerance > 0.0 ? d / plan.tolerance : (d == 0.0 ? 0.0 : kInf);
          badness = std::abs(z);
          error_value = std::abs(z);
          pval = reject ? 0.0 : 1.0;
          break;
        case ChannelTest::Exact:
          reject = !identical;
          z = reject ? kInf : 0.0;
          badness = reject ? kInf : 0.0;
          error_value = reject ? 1.0 : 0.0;
          pval = reject ? 0.0 : 1.0;
          break;
      }
      ++report.tested;
      if (reject) {
        ++report.rejected;
        pixel_failed[p] = 1;
      }
      if (finite) {
        sum_d += d;
        sum_abs_d += std::abs(d);
        sum_abs_ref += std::abs(r);
        report.max_abs_diff = std::max(report.max_abs_diff, std::abs(d));
      } else if (!identical) {
        report.max_abs_diff = kInf;
      }
      const int x = static_cast<int>(p % static_cast<size_t>(ref.width));
      const int y = static_cast<int>(p / static_cast<size_t>(ref.width));
      result.error.at(x, y, static_cast<int>(ci)) = static_cast<float>(error_value);
      result.pvalue.at(x, y, static_cast<int>(ci)) = static_cast<float>(pval);
      if (badness > worst_badness) {
        worst_badness = badness;
        result.worst = WorstPixel{x, y, plan.name, z, pval, t, r};
      }
    }
    report.mean_rel_diff = sum_abs_ref > 0.0 ? sum_d / sum_abs_ref : (sum_d == 0.0 ? 0.0 : kInf);
    report.mean_abs_rel_diff = sum_abs_ref > 0.0 ? sum_abs_d / sum_abs_ref : (sum_abs_d == 0.0 ? 0.0 : kInf);
    if (plan.test == ChannelTest::ZTest && bias_on) {
      report.bias_z = sum_var > 0.0 ? bias_sum_d / std::sqrt(sum_var) : (bias_sum_d == 0.0 ? 0.0 : kInf);
      report.bias_failed = std::abs(report.bias_z) > result.bias_z_critical;
    }
    if (plan.test == ChannelTest::ZTest && tiles_on) {
      for (size_t k = 0; k < tile_sum_d.size(); ++k) {
        const double z =
            tile_sum_var[k] > 0.0 ? tile_sum_d[k] / std::sqrt(tile_sum_var[k]) : (tile_sum_d[k] == 0.0 ? 0.0 : kInf);
        if (report.tile_x < 0 || std::abs(z) > std::abs(report.tile_z)) {
          report.tile_z = z;
          report.tile_x = static_cast<int>(k % tiles_x) * tile_size;
          report.tile_y = static_cast<int>(k / tiles_x) * tile_size;
        }
      }
      report.tile_failed = std::abs(report.tile_z) > result.tile_z_critical;
    }
    result.tested += report.tested;
    result.rejected += report.rejected;
    result.channels.push_back(std::move(report));
  }
  for (size_t p = 0; p < pixel_count; ++p) {
    result.error.pixels[p * result.error.channels.size() + static_cast<size_t>(reject_c)] = pixel_failed[p];
    result.failing_pixels += pixel_failed[p];
  }

  bool bias_failed = false;
  for (const ChannelReport& c : result.channels) bias_failed = bias_failed || c.bias_failed || c.tile_failed;
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
  return result;
}

std::string format_compare_summary(const CompareResult& r) {
  std::string s;
  bool bias_failed = false, tile_failed = false;
  for (const ChannelReport& c : r.channels) {
    bias_failed = bias_failed || c.bias_failed;
    tile_failed = tile_failed || c.tile_failed;
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
                     : tile_failed ? "; tile mean-bias test FAILED"
                                   : "");
    s += fmt::format("  per pixel-channel: alpha {:.3g} (Sidak), |z| > {:.3f}; mean-bias |z| > {:.3f}", r.alpha_pixel,
                     r.z_critical, r.bias_z_critical);
    s += r.bias_tile > 0 ? fmt::format(", per {}x{} tile |z| > {:.3f}\n", r.bias_tile, r.bias_tile, r.tile_z_critical)
                         : std::string("\n");
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
                     test_name(c.test), fmt::format("{}/{}", c.rejected, c.tested), 100.0 * c.reject_fraction(),
                     100.0 * c.mean_rel_diff, 100.0 * c.mean_abs_rel_diff,
                     c.test == ChannelTest::ZTest && std::isfinite(r.bias_z_critical)
                         ? fmt::format("{:+.2f}{}", c.bias_z, c.bias_failed ? "!" : "")
                         : std::string("-"),
                     c.tile_x >= 0
                         ? fmt::format("{:+.2f}{} at ({},{})", c.tile_z, c.tile_failed ? "!" : "", c.tile_x, c.tile_y)
                         : std::string("-"));
  if (!r.skipped.empty()) {
    std::string list;
    for (const std::string& c : r.skipped) list += (list.empty() ? "" : ", ") + c;
    s += fmt::format("  not compared (no variance; use --abs-tol-channel / --exact-channels): {}\n", list);
  }
  return s;
}

}  // namespace sylva
