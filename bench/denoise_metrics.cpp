// sylva_denoise_metrics [--rows FIRST:END] REF.exr GROUPS NAME=IMAGE.exr ...: the relative mean
// squared error of each image against a reference, minus the reference's own noise, overall and per
// group of `id.class` values (bench/README.md, "Denoised stills"). GROUPS: "crowns=4,5;grass=2;sky=0".
// --rows: only rows FIRST to END-1 count (a reference rendered as one band of rows, a tile chunk
// merged with --partial).
//
// relMSE = mean over pixels and beauty channels of ((x − r)² − Var(r)) / (r² + ε_c), Var(r) the
// reference's var.<C>, ε_c = 10⁻² · (the reference's image mean of C)²; the groups by the
// reference's pixel-centre id.class. Beauty channels: those of the reference that the image has
// (R, G, B, <band>.Y), not var.*, albedo.*, ids or features.

#include "core/error.h"
#include "core/image.h"

#include <fmt/core.h>

#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using sylva::Image;

// A beauty channel: one with a variance (var.<C>) that is not itself a variance, a feature or a
// half-buffer.
bool beauty(const Image& ref, const std::string& name) {
  for (const char* prefix : {"var.", "noisy.", "even.", "odd.", "albedo.", "feature."})
    if (name.rfind(prefix, 0) == 0) return false;
  return ref.find_channel("var." + name) >= 0;
}

std::map<std::string, std::vector<int>> parse_groups(const std::string& text) {
  std::map<std::string, std::vector<int>> groups;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ';')) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos) continue;
    std::stringstream ids(item.substr(eq + 1));
    std::string id;
    std::vector<int>& g = groups[item.substr(0, eq)];
    while (std::getline(ids, id, ',')) g.push_back(std::stoi(id));
  }
  return groups;
}

int run(int argc, char** argv) {
  int y0 = 0, y1 = -1;
  if (argc > 2 && std::string(argv[1]) == "--rows") {
    const std::string rows = argv[2];
    y0 = std::stoi(rows.substr(0, rows.find(':')));
    y1 = std::stoi(rows.substr(rows.find(':') + 1));
    argc -= 2;
    argv += 2;
  }
  if (argc < 4) {
    std::fprintf(stderr, "usage: sylva_denoise_metrics [--rows FIRST:END] REF.exr GROUPS NAME=IMAGE.exr ...\n");
    return 2;
  }
  const Image ref = sylva::read_exr(argv[1]);
  if (y1 < 0) y1 = ref.height;
  if (y0 < 0 || y0 >= y1 || y1 > ref.height) throw sylva::Error("--rows: not inside the reference");
  const double pixel_count = static_cast<double>(ref.width) * (y1 - y0);
  const auto groups = parse_groups(argv[2]);
  const int cls = ref.find_channel("id.class");
  if (cls < 0) throw sylva::Error("the reference has no id.class");
  std::vector<int> channels;
  for (int c = 0; c < ref.channel_count(); ++c)
    if (beauty(ref, ref.channels[c])) channels.push_back(c);
  std::vector<double> eps;
  for (const int c : channels) {
    double m = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < ref.width; ++x) m += ref.at(x, y, c);
    m /= pixel_count;
    eps.push_back(1e-2 * m * m);
  }
  std::string header = "image\tall";
  for (const auto& [name, ids] : groups) header += "\t" + name;
  std::printf("%s\n", header.c_str());
  for (int i = 3; i < argc; ++i) {
    const std::string arg = argv[i];
    const size_t eq = arg.find('=');
    const Image im = sylva::read_exr(arg.substr(eq + 1));
    if (im.width != ref.width || im.height != ref.height) throw sylva::Error(arg + ": not the reference's size");
    std::map<int, std::pair<double, double>> per_class;  // class → (sum, count)
    double sum = 0, count = 0;
    for (size_t k = 0; k < channels.size(); ++k) {
      const std::string& name = ref.channels[channels[k]];
      const int ic = im.find_channel(name), rv = ref.find_channel("var." + name);
      if (ic < 0 || rv < 0) throw sylva::Error(arg + ": no " + name + " or var." + name);
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < ref.width; ++x) {
          const double r = ref.at(x, y, channels[k]), d = im.at(x, y, ic) - r;
          const double e = (d * d - ref.at(x, y, rv)) / (r * r + eps[k]);
          auto& pc = per_class[static_cast<int>(ref.at(x, y, cls))];
          pc.first += e;
          pc.second += 1;
          sum += e;
          count += 1;
        }
    }
    std::string line = fmt::format("{}\t{:.5g}", arg.substr(0, eq), sum / count);
    for (const auto& [name, ids] : groups) {
      double s = 0, n = 0;
      for (const int id : ids)
        if (const auto it = per_class.find(id); it != per_class.end()) {
          s += it->second.first;
          n += it->second.second;
        }
      line += n > 0 ? fmt::format("\t{:.5g}", s / n) : "\t-";
    }
    std::printf("%s\n", line.c_str());
  }
  // The pixel share of each group.
  std::string shares = "pixels\t1";
  std::map<int, double> pixels;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < ref.width; ++x) pixels[static_cast<int>(ref.at(x, y, cls))] += 1;
  for (const auto& [name, ids] : groups) {
    double n = 0;
    for (const int id : ids) n += pixels.count(id) ? pixels[id] : 0;
    shares += fmt::format("\t{:.3f}", n / pixel_count);
  }
  std::printf("%s\n", shares.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sylva_denoise_metrics: %s\n", e.what());
    return 1;
  }
}
