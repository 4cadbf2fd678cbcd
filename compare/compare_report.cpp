#include "compare/compare_report.h"

#include "core/color.h"
#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>

namespace sylva {
namespace {

// One preview: a colour triple of a layer (R,G,B or X,Y,Z) or a single channel shown grey.
struct PreviewItem {
  std::string label;  // shown in the HTML
  std::string slug;   // file name stem
  std::array<std::string, 3> channels;
  std::vector<size_t> result_channels;  // indices into CompareResult::channels / error planes
  int64_t tested = 0, rejected = 0;
  bool bias_failed = false;
  bool radiometric = true;  // z-test/threshold channels shown as is; others mapped from the reference range
  double share() const { return tested > 0 ? static_cast<double>(rejected) / static_cast<double>(tested) : 0.0; }
  bool failing() const { return rejected > 0 || bias_failed; }
};

std::string layer_of(const std::string& name) {
  const size_t dot = name.rfind('.');
  return dot == std::string::npos ? "" : name.substr(0, dot);
}
std::string suffix_of(const std::string& name) {
  const size_t dot = name.rfind('.');
  return dot == std::string::npos ? name : name.substr(dot + 1);
}

std::string slugify(const std::string& s) {
  std::string out;
  for (char ch : s) out += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return out.empty() ? "image" : out;
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

std::vector<PreviewItem> make_items(const CompareResult& result) {
  // Group tested channels by layer, keeping first-seen order.
  std::vector<std::string> layers;
  std::map<std::string, std::vector<size_t>> members;
  for (size_t i = 0; i < result.channels.size(); ++i) {
    const std::string layer = layer_of(result.channels[i].name);
    if (!members.count(layer)) layers.push_back(layer);
    members[layer].push_back(i);
  }
  std::vector<PreviewItem> items;
  auto add = [&](PreviewItem item) {
    for (size_t i : item.result_channels) {
      const ChannelReport& c = result.channels[i];
      item.tested += c.tested;
      item.rejected += c.rejected;
      item.bias_failed = item.bias_failed || c.regions_failed > 0;
      item.radiometric = item.radiometric && (c.test == ChannelTest::ZTest || c.test == ChannelTest::Threshold);
    }
    items.push_back(std::move(item));
  };
  for (const std::string& layer : layers) {
    std::vector<size_t> rest = members[layer];
    for (const std::array<const char*, 3>& triple :
         {std::array<const char*, 3>{"R", "G", "B"}, std::array<const char*, 3>{"X", "Y", "Z"}}) {
      std::vector<size_t> found;
      for (const char* s : triple)
        for (size_t i : rest)
          if (suffix_of(result.channels[i].name) == s) found.push_back(i);
      if (found.size() != 3) continue;
      PreviewItem item;
      item.label = layer.empty() ? std::string("rgb") : layer;
      item.slug = slugify(item.label);
      for (size_t k = 0; k < 3; ++k) item.channels[k] = result.channels[found[k]].name;
      item.result_channels = found;
      std::erase_if(rest, [&](size_t i) { return std::find(found.begin(), found.end(), i) != found.end(); });
      add(std::move(item));
    }
    for (size_t i : rest) {
      PreviewItem item;
      item.label = result.channels[i].name;
      item.slug = slugify(item.label);
      item.channels = {item.label, item.label, item.label};
      item.result_channels = {i};
      add(std::move(item));
    }
  }
  // Unique slugs (a layer "rgb" next to bare R,G,B, say).
  std::map<std::string, int> seen;
  for (PreviewItem& item : items)
    if (int n = seen[item.slug]++; n > 0) item.slug = fmt::format("{}_{}", item.slug, n);
  std::stable_sort(items.begin(), items.end(), [](const PreviewItem& a, const PreviewItem& b) {
    if (a.failing() != b.failing()) return a.failing();
    return a.share() > b.share();
  });
  return items;
}

std::string format_share(double share) { return fmt::format("{:.4g}%", 100.0 * share); }

// Failing local tests of the item's channels over the reject preview: id regions (class, object,
// sky) tinted magenta, tiles and grid cells outlined in yellow.
void mark_failing_regions(const Image& ref, const CompareResult& result, const PreviewItem& item,
                          std::vector<uint8_t>& rgb) {
  const auto set = [&](int x, int y, std::array<uint8_t, 3> colour, bool blend) {
    const size_t p = (static_cast<size_t>(y) * static_cast<size_t>(ref.width) + static_cast<size_t>(x)) * 3;
    for (size_t k = 0; k < 3; ++k) rgb[p + k] = blend ? static_cast<uint8_t>((rgb[p + k] + colour[k]) / 2) : colour[k];
  };
  std::vector<const RegionTest*> failing;
  for (const RegionTest& t : result.regions)
    if (t.failed() && t.kind != RegionKind::Image &&
        std::any_of(item.channels.begin(), item.channels.end(), [&](const std::string& c) { return c == t.channel; }))
      failing.push_back(&t);
  // Regions first (each pixel tinted once, however many channels fail there), then the outlines.
  std::vector<uint8_t> tinted(static_cast<size_t>(ref.width) * static_cast<size_t>(ref.height), 0);
  for (const RegionTest* t : failing) {
    if (t->kind == RegionKind::Tile || t->kind == RegionKind::Grid) continue;
    const int c = ref.find_channel(t->kind == RegionKind::Class      ? "id.class"
                                   : t->kind == RegionKind::Object   ? "id.object"
                                   : t->kind == RegionKind::Material ? "id.material"
                                                                     : "id.instance");
    if (c < 0) continue;
    for (int y = t->y0; y < t->y1; ++y)
      for (int x = t->x0; x < t->x1; ++x) {
        uint8_t& done = tinted[static_cast<size_t>(y) * static_cast<size_t>(ref.width) + static_cast<size_t>(x)];
        if (done == 0 && static_cast<int64_t>(ref.at(x, y, c)) == t->label) {
          set(x, y, {255, 0, 255}, true);
          done = 1;
        }
      }
  }
  for (const RegionTest* t : failing)
    if (t->kind == RegionKind::Tile || t->kind == RegionKind::Grid)
      for (int y = t->y0; y < t->y1; ++y)
        for (int x = t->x0; x < t->x1; ++x)
          if (x == t->x0 || x == t->x1 - 1 || y == t->y0 || y == t->y1 - 1) set(x, y, {255, 220, 0}, false);
}

// Writes the item's previews: test, reference and |diff|·k, and the rejecting pixels over the dimmed
// reference (tiles failing the local bias test outlined).
void write_item_previews(const std::filesystem::path& dir, const Image& test, const Image& ref,
                         const CompareResult& result, const ReportOptions& options, const PreviewItem& item) {
  // The item's three channels of test, reference and |diff|·k as R,G,B images. Radiometric
  // channels keep their values (linear Rec.709 for the view); data channels (depth, normals,
  // ids) are mapped from the reference's [min, max] to [0, 1].
  float lo = 0.0f, span = 1.0f;
  if (!item.radiometric) {
    float hi = -std::numeric_limits<float>::infinity();
    lo = std::numeric_limits<float>::infinity();
    for (const std::string& name : item.channels) {
      const int c = ref.find_channel(name);
      for (int y = 0; y < ref.height; ++y)
        for (int x = 0; x < ref.width; ++x)
          if (const float v = ref.at(x, y, c); std::isfinite(v)) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
          }
    }
    if (!(hi > lo)) {
      span = std::isfinite(lo) && lo != 0.0f ? std::abs(lo) : 1.0f;
      lo = std::isfinite(lo) ? lo - span : 0.0f;
    } else {
      span = hi - lo;
    }
  }
  Image t3 = make_image(ref.width, ref.height, {"R", "G", "B"});
  Image r3 = t3, d3 = t3;
  for (int c = 0; c < 3; ++c) {
    const int tc = test.find_channel(item.channels[static_cast<size_t>(c)]);
    const int rc = ref.find_channel(item.channels[static_cast<size_t>(c)]);
    for (int y = 0; y < ref.height; ++y)
      for (int x = 0; x < ref.width; ++x) {
        const float t = test.at(x, y, tc), r = ref.at(x, y, rc);
        t3.at(x, y, c) = (t - lo) / span;
        r3.at(x, y, c) = (r - lo) / span;
        d3.at(x, y, c) = std::abs(t - r) / span * options.diff_scale;
      }
  }
  PreviewOptions preview;
  preview.view = options.view;
  preview.exposure_ev = item.radiometric ? options.exposure_ev : 0.0f;
  write_png_preview(dir / (item.slug + "_test.png"), t3, preview);
  const std::vector<uint8_t> ref_rgb = make_preview_rgb8(r3, preview);
  write_png_rgb8(dir / (item.slug + "_ref.png"), ref.width, ref.height, ref_rgb);
  write_png_preview(dir / (item.slug + "_diff.png"), d3, preview);

  // Rejecting pixels of this item in red over the dimmed reference.
  std::vector<uint8_t> reject_rgb(ref_rgb.size());
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) {
      const size_t p = static_cast<size_t>(y) * static_cast<size_t>(ref.width) + static_cast<size_t>(x);
      bool rejected = false;
      for (size_t i : item.result_channels) {
        const ChannelReport& c = result.channels[i];
        const float e = result.error.at(x, y, static_cast<int>(i));
        rejected = rejected || (c.test == ChannelTest::ZTest   ? (!std::isfinite(e) || e > result.z_critical)
                                : c.test == ChannelTest::Exact ? e > 0.0f
                                                               : (!std::isfinite(e) || e > 1.0f));
      }
      for (size_t k = 0; k < 3; ++k)
        reject_rgb[p * 3 + k] = rejected ? (k == 0 ? 255 : 0) : static_cast<uint8_t>(ref_rgb[p * 3 + k] * 2 / 5);
    }
  mark_failing_regions(ref, result, item, reject_rgb);
  write_png_rgb8(dir / (item.slug + "_reject.png"), ref.width, ref.height, reject_rgb);
}

// The page's head, verdict and statistics.
std::string html_verdict(const CompareResult& result, const ReportOptions& options) {
  std::string h;
  const char* verdict = result.passed ? "PASS" : "FAIL";
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += fmt::format("<title>sylva compare: {} — {}</title>\n", verdict, html_escape(options.test_label));
  h += "<style>\n"
       "body{font-family:sans-serif;margin:1.5em;background:#1e1e1e;color:#ddd}\n"
       "a{color:#8cf} table{border-collapse:collapse;margin:0.5em 0}\n"
       "td,th{padding:0.2em 0.7em;border-bottom:1px solid #444;text-align:right}\n"
       "td:first-child,th:first-child{text-align:left}\n"
       ".fail{color:#ff6b6b;font-weight:bold} .pass{color:#7ddc7d;font-weight:bold}\n"
       ".row{display:flex;flex-wrap:wrap;gap:1em} figure{margin:0}\n"
       "figure img{image-rendering:pixelated;min-width:256px;border:1px solid #555}\n"
       "figcaption{font-size:0.85em;color:#aaa} pre{background:#111;padding:0.7em;overflow-x:auto}\n"
       "</style>\n</head>\n<body>\n";
  h += fmt::format("<h1>sylva compare: <span class=\"{}\" id=\"verdict\">{}</span></h1>\n",
                   result.passed ? "pass" : "fail", verdict);
  h += fmt::format("<p>Test <code>{}</code> against reference <code>{}</code>, {}&times;{} pixels.</p>\n",
                   html_escape(options.test_label), html_escape(options.ref_label), result.width, result.height);
  if (!options.command.empty()) h += fmt::format("<p><code>{}</code></p>\n", html_escape(options.command));
  if (result.threshold_mode)
    h += fmt::format(
        "<p>Threshold test (Cycles/idiff style): failing pixels <b>{}</b> ({} of {}), limit "
        "{}.</p>\n",
        format_share(result.reject_fraction), result.failing_pixels, static_cast<int64_t>(result.width) * result.height,
        format_share(result.limit));
  else
    h += fmt::format(
        "<p>Per-pixel z-test: rejecting pixel-channels <b>{}</b> ({} of {}), limit {}; per "
        "pixel-channel &alpha; = {:.3g} (Šidák), |z| &gt; {:.3f}.</p>\n",
        format_share(result.reject_fraction), result.rejected, result.tested, format_share(result.limit),
        result.alpha_pixel, result.z_critical);
  if (result.worst.x >= 0)
    h += fmt::format(
        "<p>Worst pixel ({}, {}) channel <code>{}</code>: test {:.6g}, reference {:.6g}, {} "
        "{:.4g}, p "
        "{:.3g}.</p>\n",
        result.worst.x, result.worst.y, html_escape(result.worst.channel), result.worst.test, result.worst.ref,
        result.threshold_mode ? "d/T" : "z", result.worst.z, result.worst.p);
  return h;
}

// The channel table, failing channels first, and what was not compared.
std::string html_channels(const CompareResult& result) {
  std::string h;
  std::vector<const ChannelReport*> channels;
  for (const ChannelReport& c : result.channels) channels.push_back(&c);
  std::stable_sort(channels.begin(), channels.end(), [](const ChannelReport* a, const ChannelReport* b) {
    const bool fa = a->rejected > 0 || a->regions_failed > 0;
    const bool fb = b->rejected > 0 || b->regions_failed > 0;
    if (fa != fb) return fa;
    return a->reject_fraction() > b->reject_fraction();
  });
  h += "<h2>Channels</h2>\n<table "
       "id=\"channels\">\n<tr><th>channel</th><th>test</th><th>rejected</th><th>share</th>"
       "<th>mean rel. diff</th><th>mean |rel. diff|</th><th>max |diff|</th><th>bias "
       "z</th><th>worst tile z</th></tr>\n";
  for (const ChannelReport* c : channels) {
    const bool failing = c->rejected > 0 || c->regions_failed > 0;
    const char* mode = c->test == ChannelTest::ZTest       ? "z-test"
                       : c->test == ChannelTest::Threshold ? "threshold"
                       : c->test == ChannelTest::Exact     ? "exact"
                                                           : "abs. tolerance";
    h += fmt::format(
        "<tr class=\"{}\"><td>{}</td><td>{}</td><td>{} / {}</td><td>{}</td><td>{:+.4g}%</td>"
        "<td>{:.4g}%</td><td>{:.4g}</td><td>{}</td><td>{}</td></tr>\n",
        failing ? "fail" : "", html_escape(c->name), mode, c->rejected, c->tested, format_share(c->reject_fraction()),
        100.0 * c->mean_rel_diff, 100.0 * c->mean_abs_rel_diff, c->max_abs_diff,
        c->test == ChannelTest::ZTest && std::isfinite(result.bias_z_critical)
            ? fmt::format("{:+.2f}{}", c->bias_z, c->bias_failed ? " (fails)" : "")
            : std::string("&ndash;"),
        c->tile_x >= 0
            ? fmt::format("{:+.2f}{} at ({}, {})", c->tile_z, c->tile_failed ? " (fails)" : "", c->tile_x, c->tile_y)
            : std::string("&ndash;"));
  }
  h += "</table>\n";
  if (!result.skipped.empty()) {
    std::string list;
    for (const std::string& c : result.skipped) list += (list.empty() ? "" : ", ") + html_escape(c);
    h += fmt::format("<p>Not compared (no variance, no tolerance): {}.</p>\n", list);
  }
  if (!result.variance_model.empty())
    h += fmt::format("<p>Variance of the difference: {}.</p>\n", html_escape(result.variance_model));
  return h;
}

// The failing local tests, most significant first: where, z, mean shift, scatter.
std::string html_regions(const CompareResult& result) {
  if (result.family_size == 0) return {};
  std::vector<const RegionTest*> failing;
  for (const RegionTest& t : result.regions)
    if (t.failed()) failing.push_back(&t);
  std::stable_sort(failing.begin(), failing.end(), [](const RegionTest* a, const RegionTest* b) {
    return std::min(a->bias_p_holm, a->variance_p_holm) < std::min(b->bias_p_holm, b->variance_p_holm);
  });
  std::string h = fmt::format(
      "<h2>Local tests</h2>\n<p>{} bias and variance tests over the whole image{}{} and the id regions (class, "
      "object, sky), Holm at &alpha; = {:.3g} (first |z| &gt; {:.3f}): <b>{} failing</b>.</p>\n",
      result.family_size, result.bias_tile > 0 ? fmt::format(", {0}&times;{0} tiles", result.bias_tile) : std::string(),
      result.bias_grid_cell > 0 ? fmt::format(", {0}&times;{0} grid cells", result.bias_grid_cell) : std::string(),
      result.bias_alpha, result.bias_z_critical, failing.size());
  if (failing.empty()) return h;
  h += "<table id=\"regions\">\n<tr><th>channel</th><th>region</th><th>where (x, y)</th><th>pixels</th>"
       "<th>bias z</th><th>mean shift</th><th>scatter</th><th>Holm p (bias, scatter)</th></tr>\n";
  for (size_t i = 0; i < failing.size() && i < 200; ++i) {
    const RegionTest& t = *failing[i];
    h += fmt::format(
        "<tr class=\"fail\"><td>{}</td><td>{}</td><td>{}&ndash;{}, {}&ndash;{}</td><td>{}</td><td>{:+.2f}{}</td>"
        "<td>{:+.3g}%</td><td>{:.3g}{}</td><td>{:.3g}, {:.3g}</td></tr>\n",
        html_escape(t.channel), html_escape(region_name(t)), t.x0, t.x1 - 1, t.y0, t.y1 - 1, t.pixels, t.bias_z,
        t.bias_failed ? " (fails)" : "", 100.0 * t.mean_shift, t.variance_ratio, t.variance_failed ? " (fails)" : "",
        t.bias_p_holm, t.variance_p_holm);
  }
  h += "</table>\n";
  if (failing.size() > 200) h += fmt::format("<p>&hellip; and {} more.</p>\n", failing.size() - 200);
  return h;
}

// The preview images, failing groups first.
std::string html_images(const CompareResult& result, const ReportOptions& options,
                        const std::vector<PreviewItem>& items) {
  std::string h;
  h += fmt::format(
      "<h2>Images</h2>\n<p>|diff| is scaled by k = {:g}; rejecting pixels are red over the dimmed "
      "reference; a failing tile or grid cell of the local tests is outlined in yellow, a failing id region "
      "(class, object, sky) tinted magenta. Previews use the "
      "OCIO view &ldquo;{}&rdquo;; data channels (depth, normals, ids) are "
      "mapped from the reference's range to black&ndash;white.</p>\n",
      options.diff_scale, html_escape(options.view));
  for (const PreviewItem& item : items) {
    h += fmt::format(
        "<section class=\"item\" id=\"item-{}\">\n<h3>{} <span class=\"{}\">{}</span> &mdash; {} "
        "rejected ({} of {}){}</h3>\n<div class=\"row\">\n",
        item.slug, html_escape(item.label), item.failing() ? "fail" : "pass", item.failing() ? "FAIL" : "pass",
        format_share(item.share()), item.rejected, item.tested, item.bias_failed ? ", local tests" : "");
    const std::array<std::pair<const char*, std::string>, 4> figures{
        std::pair{"_test.png", "test"}, std::pair{"_ref.png", "reference"},
        std::pair{"_diff.png", fmt::format("|diff| &times; {:g}", options.diff_scale)},
        std::pair{"_reject.png", "rejecting pixels"}};
    for (const auto& [suffix, caption] : figures)
      h += fmt::format(
          "<figure><img src=\"{0}{1}\" width=\"{2}\" "
          "alt=\"{3}\"><figcaption>{3}</figcaption></figure>\n",
          item.slug, suffix, std::max(256, result.width), caption);
    h += "</div>\n</section>\n";
  }
  return h;
}

// The report page: verdict, statistics, channels (failing first) and the previews (failing first).
std::string report_html(const CompareResult& result, const ReportOptions& options,
                        const std::vector<PreviewItem>& items) {
  std::string h;
  h += html_verdict(result, options);
  h += html_channels(result);
  h += html_regions(result);
  h += html_images(result, options, items);
  h += "<h2>Files</h2>\n<p><a href=\"test.exr\">test.exr</a> &middot; <a "
       "href=\"ref.exr\">ref.exr</a> &middot; "
       "<a href=\"error.exr\">error.exr</a> (|z| per channel, reject.Y mask) &middot; <a "
       "href=\"pvalue.exr\">"
       "pvalue.exr</a></p>\n";
  h += "<h2>Summary</h2>\n<pre>" + html_escape(format_compare_summary(result)) + "</pre>\n</body>\n</html>\n";
  return h;
}

}  // namespace

void write_compare_report(const std::filesystem::path& dir, const Image& test, const Image& ref,
                          const CompareResult& result, const ReportOptions& options) {
  const std::vector<std::string> views = ocio_views();
  if (std::find(views.begin(), views.end(), options.view) == views.end()) {
    float probe[3] = {0.0f, 0.0f, 0.0f};
    apply_display_transform(probe, 1, options.view);  // throws, naming the available views
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw Error(dir.string() + ": cannot create report directory" + (ec ? ": " + ec.message() : ""));

  write_exr(dir / "test.exr", test);
  write_exr(dir / "ref.exr", ref);
  write_exr(dir / "error.exr", result.error);
  write_exr(dir / "pvalue.exr", result.pvalue);

  const std::vector<PreviewItem> items = make_items(result);
  for (const PreviewItem& item : items) write_item_previews(dir, test, ref, result, options, item);
  write_text_file(dir / "index.html", report_html(result, options, items));
}

}  // namespace sylva
