// sylva_replica_error [--classes ID,...] [--channels R,G,B] [--spp-png OUT.png [--scale N]] A.exr B.exr
// [...]:
// the median relative error of a render measured without a reference, from R >= 2 independent
// replicas of it (the same configuration, different seeds): bench/adaptive.sh, bench/README.md
// "Adaptive sampling against uniform".
//
// Per pixel p and channel c, over the replicas r: the mean m and the unbiased variance
// s² = Σ (x_r − m)² / (R − 1), so one replica's relative error is e_pc = s / |m| (infinite where
// m = 0), and the pixel's e_p = √(mean over c of e_pc²). The same from the renders' own variance
// of the mean: v_pc = mean over r of var.<c>, e'_pc = √v / |m|. Pixels counted: those whose
// `id.class` is in --classes in the first replica (every pixel without --classes). Printed, one
// "key value" per line:
//   pixels N            pixels counted
//   median E            median over them of e_p; also p25, p75 and median.<c> (of e_pc)
//   median_var E        median of e'_p (the var.<c> channels)
//   mean_spp S          mean (and median_spp) over them and the replicas of the `spp` channel (where present),
//   at_max_spp F        and the fraction of those equal to the largest spp of the replicas
// --spp-png: the first replica's image (auto exposure) beside its spp map (grey, log2 spp from 1
// to the largest), each pixel N×N (default 1). Exit 0; 2 on a usage or file error.

#include "core/error.h"
#include "core/image.h"
#include "pipeline/outputs.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Options {
  std::set<uint32_t> classes;  // empty: every pixel
  std::vector<std::string> channels{"R", "G", "B"};
  std::string spp_png;
  int scale = 1;
  std::vector<std::string> files;
};

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--classes" || a == "--channels" || a == "--spp-png" || a == "--scale") && i + 1 < argc) {
      const std::string v = argv[++i];
      if (a == "--classes")
        for (const std::string& id : split(v)) o.classes.insert(static_cast<uint32_t>(std::stoul(id)));
      else if (a == "--channels")
        o.channels = split(v);
      else if (a == "--scale")
        o.scale = std::clamp(std::stoi(v), 1, 64);
      else
        o.spp_png = v;
    } else {
      o.files.push_back(a);
    }
  }
  if (o.files.size() < 2 || o.channels.empty())
    throw sylva::Error(
        "usage: sylva_replica_error "
        "[--classes ID,...] [--channels R,G,B] "
        "[--spp-png OUT.png [--scale N]] A.exr B.exr [...]");
  return o;
}

int channel(const sylva::Image& image, const std::string& name, const std::string& file) {
  const int c = image.find_channel(name);
  if (c < 0) throw sylva::Error(file + ": no channel " + name);
  return c;
}

// The q-quantile, interpolated linearly between the order statistics (q = 0.5: the median).
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double at = q * static_cast<double>(v.size() - 1);
  const auto k = static_cast<size_t>(at);
  return k + 1 < v.size() ? v[k] + (at - static_cast<double>(k)) * (v[k + 1] - v[k]) : v[k];
}

// The per-pixel relative errors of the counted pixels, and the spp figures.
struct Errors {
  std::vector<double> pixel, pixel_var;
  std::vector<std::vector<double>> per_channel;
  std::vector<double> spp;  // of the counted pixels, every replica
  double spp_sum = 0, spp_max = 0;
  size_t spp_count = 0, at_max = 0;
};

Errors measure(const Options& o, const std::vector<sylva::Image>& images) {
  const sylva::Image& first = images.front();
  const size_t nc = o.channels.size(), nr = images.size();
  const int id_class = o.classes.empty() ? -1 : channel(first, "id.class", o.files[0]);
  std::vector<std::vector<int>> value(nr), var(nr);
  std::vector<int> spp(nr, -1);
  for (size_t r = 0; r < nr; ++r) {
    if (images[r].width != first.width || images[r].height != first.height)
      throw sylva::Error(o.files[r] + ": not the size of " + o.files[0]);
    for (const std::string& c : o.channels) {
      value[r].push_back(channel(images[r], c, o.files[r]));
      var[r].push_back(channel(images[r], "var." + c, o.files[r]));
    }
    spp[r] = images[r].find_channel("spp");
  }
  Errors e;
  e.per_channel.resize(nc);
  for (size_t r = 0; r < nr; ++r)
    for (int y = 0; y < first.height && spp[r] >= 0; ++y)
      for (int x = 0; x < first.width; ++x) e.spp_max = std::max(e.spp_max, double(images[r].at(x, y, spp[r])));
  for (int y = 0; y < first.height; ++y)
    for (int x = 0; x < first.width; ++x) {
      if (id_class >= 0 && o.classes.count(static_cast<uint32_t>(first.at(x, y, id_class))) == 0) continue;
      double sum2 = 0, sum2_var = 0;
      for (size_t c = 0; c < nc; ++c) {
        double m = 0, v = 0;
        for (size_t r = 0; r < nr; ++r) m += images[r].at(x, y, value[r][c]) / double(nr);
        double s2 = 0;
        for (size_t r = 0; r < nr; ++r) {
          const double d = images[r].at(x, y, value[r][c]) - m;
          s2 += d * d / double(nr - 1);
          v += images[r].at(x, y, var[r][c]) / double(nr);
        }
        const double rel2 = m != 0 ? s2 / (m * m) : std::numeric_limits<double>::infinity();
        e.per_channel[c].push_back(std::sqrt(rel2));
        sum2 += rel2 / double(nc);
        sum2_var += (m != 0 ? v / (m * m) : std::numeric_limits<double>::infinity()) / double(nc);
      }
      e.pixel.push_back(std::sqrt(sum2));
      e.pixel_var.push_back(std::sqrt(sum2_var));
      for (size_t r = 0; r < nr; ++r) {
        if (spp[r] < 0) continue;
        const double n = images[r].at(x, y, spp[r]);
        e.spp.push_back(n);
        e.spp_sum += n;
        e.spp_count += 1;
        e.at_max += n == e.spp_max ? 1 : 0;
      }
    }
  return e;
}

// The first replica (auto exposure) and, to its right, its spp map: grey log2(spp) / log2(max).
void write_spp_png(const std::string& path, const sylva::Image& image, const std::string& file, int scale) {
  const int spp = channel(image, "spp", file);
  sylva::PreviewOptions options;
  options.exposure_ev = sylva::auto_exposure_ev(image, options.channels);
  const std::vector<uint8_t> preview = sylva::make_preview_rgb8(image, options);
  double most = 1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) most = std::max(most, double(image.at(x, y, spp)));
  const int w = image.width, out_w = 2 * w * scale, out_h = image.height * scale;
  std::vector<uint8_t> out(static_cast<size_t>(out_w) * static_cast<size_t>(out_h) * 3);
  for (int oy = 0; oy < out_h; ++oy)
    for (int ox = 0; ox < out_w; ++ox) {
      const int x = (ox / scale) % w, y = oy / scale;
      const double n = std::max(1.0, double(image.at(x, y, spp)));
      const auto grey = static_cast<uint8_t>(std::lround(255.0 * std::log2(n) / std::max(1.0, std::log2(most))));
      for (int k = 0; k < 3; ++k)
        out[(static_cast<size_t>(oy) * out_w + ox) * 3 + k] =
            ox < w * scale ? preview[(static_cast<size_t>(y) * w + x) * 3 + k] : grey;
    }
  sylva::write_png_rgb8(path, out_w, out_h, out);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    std::vector<sylva::Image> images;
    for (const std::string& f : o.files) images.push_back(sylva::read_exr(f));
    const Errors e = measure(o, images);
    fmt::print("pixels {}\nmedian {:.6g}\np25 {:.6g}\np75 {:.6g}\nmedian_var {:.6g}\n", e.pixel.size(),
               quantile(e.pixel, 0.5), quantile(e.pixel, 0.25), quantile(e.pixel, 0.75), quantile(e.pixel_var, 0.5));
    for (size_t c = 0; c < o.channels.size(); ++c)
      fmt::print("median.{} {:.6g}\n", o.channels[c], quantile(e.per_channel[c], 0.5));
    if (e.spp_count > 0)
      fmt::print("mean_spp {:.6g}\nmedian_spp {:.6g}\nmax_spp {:.6g}\nat_max_spp {:.6g}\n",
                 e.spp_sum / double(e.spp_count), quantile(e.spp, 0.5), e.spp_max,
                 double(e.at_max) / double(e.spp_count));
    if (!o.spp_png.empty()) write_spp_png(o.spp_png, images.front(), o.files.front(), o.scale);
    return 0;
  } catch (const std::exception& ex) {
    fmt::print(stderr, "sylva_replica_error: {}\n", ex.what());
    return 2;
  }
}
