// sylva_denoise_metrics [--rows FIRST:END] REF.exr GROUPS NAME=IMAGE.exr ...: the relative mean
// squared error of each image against a reference, minus the reference's own noise, overall and per
// group of `id.class` values (bench/README.md, "Denoised stills"). GROUPS: "crowns=4,5;grass=2;sky=0".
// --rows: only rows FIRST to END-1 count (a reference rendered as one band of rows, a tile chunk
// merged with --partial).
//
// relMSE (compare/rel_mse.h) = mean over pixels and beauty channels of ((x − r)² − Var(r)) /
// (r² + ε_c), Var(r) the reference's var.<C>, ε_c = 10⁻² · (the reference's image mean of C)²; the
// groups by the reference's pixel-centre id.class. Beauty channels: the reference's (R, G, B,
// <band>.Y), not var.*, albedo.*, ids or features.

#include "compare/rel_mse.h"
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
  sylva::RelMseOptions options;
  options.channels = sylva::beauty_channels(ref);
  options.epsilon_scale = 1e-2;
  options.epsilon = sylva::RelMseEpsilon::square_mean;
  options.subtract_reference_variance = true;
  options.row_begin = y0;
  options.row_end = y1;
  std::string header = "image\tall";
  for (const auto& [name, ids] : groups) header += "\t" + name;
  std::printf("%s\n", header.c_str());
  for (int i = 3; i < argc; ++i) {
    const std::string arg = argv[i];
    const size_t eq = arg.find('=');
    const Image im = sylva::read_exr(arg.substr(eq + 1));
    const std::vector<double> errors = sylva::relative_squared_errors(im, ref, options);
    std::map<int, std::pair<double, double>> per_class;  // class → (sum, count)
    double sum = 0;
    size_t p = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < ref.width; ++x, ++p) {
        auto& pc = per_class[static_cast<int>(ref.at(x, y, cls))];
        pc.first += errors[p];
        pc.second += 1;
        sum += errors[p];
      }
    const double count = static_cast<double>(errors.size());
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
