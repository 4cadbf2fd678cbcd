// sylva_rel_mse TEST.exr REF.exr [--channels R,G,B]: the relative mean squared error of a render
// against a converged reference, as issue 41 defines it (compare/rel_mse.h: the mean over pixels of
// (test − ref)² / (ref² + 10⁻⁴ · mean ref²), averaged over the channels), printed on one line.
// bench/efficiency.sh multiplies it by the render's CPU-seconds. Exit 0; 2 on a usage or file error.

#include "compare/rel_mse.h"
#include "core/image.h"

#include <cstdio>
#include <exception>
#include <sstream>
#include <string>

int main(int argc, char** argv) {
  sylva::RelMseOptions options = sylva::issue41_rel_mse();
  if (argc == 5 && std::string(argv[3]) == "--channels") {
    options.channels.clear();
    std::stringstream names(argv[4]);
    for (std::string name; std::getline(names, name, ',');) options.channels.push_back(name);
  } else if (argc != 3) {
    std::fprintf(stderr, "usage: sylva_rel_mse TEST.exr REF.exr [--channels R,G,B]\n");
    return 2;
  }
  try {
    std::printf("%.6g\n", sylva::relative_mse(sylva::read_exr(argv[1]), sylva::read_exr(argv[2]), options));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sylva_rel_mse: %s\n", e.what());
    return 2;
  }
}
