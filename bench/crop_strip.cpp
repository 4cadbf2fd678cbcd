// sylva_crop_strip OUT.png X Y W H EXPOSURE VIEW IN.exr ...: the same W×H window of each image, at
// 1:1, side by side (left to right in argument order, 2 white pixels apart), through one preview
// transform (core/image.h: the same exposure in stops and OCIO view for all), as one PNG. EXPOSURE
// "auto": the previews' auto exposure (pipeline/outputs.h) of the first image's whole frame. For the
// before/after crops of docs/denoise.md (bench/denoise_bench.sh --crops).

#include "core/error.h"
#include "core/image.h"
#include "pipeline/outputs.h"

#include <fmt/core.h>

#include <cstdio>
#include <string>
#include <vector>

namespace {

constexpr int kGap = 2;  // white pixels between two crops

}  // namespace

int main(int argc, char** argv) {
  if (argc < 9) {
    fmt::print(stderr, "usage: sylva_crop_strip OUT.png X Y W H EXPOSURE VIEW IN.exr ...\n");
    return 2;
  }
  try {
    const int x0 = std::stoi(argv[2]), y0 = std::stoi(argv[3]), w = std::stoi(argv[4]), h = std::stoi(argv[5]);
    sylva::PreviewOptions options;
    options.exposure_ev = std::string(argv[6]) == "auto"
                              ? sylva::auto_exposure_ev(sylva::read_exr(argv[8]), options.channels)
                              : std::stof(argv[6]);
    options.view = argv[7];
    const int n = argc - 8;
    const int strip_w = n * w + (n - 1) * kGap;
    std::vector<uint8_t> strip(static_cast<size_t>(strip_w) * static_cast<size_t>(h) * 3, 255);
    for (int i = 0; i < n; ++i) {
      const sylva::Image image = sylva::read_exr(argv[8 + i]);
      if (x0 < 0 || y0 < 0 || w <= 0 || h <= 0 || x0 + w > image.width || y0 + h > image.height)
        throw sylva::Error(fmt::format("{}: the window {}x{} at ({}, {}) is not inside the {}x{} image", argv[8 + i], w,
                                       h, x0, y0, image.width, image.height));
      const std::vector<uint8_t> rgb = sylva::make_preview_rgb8(image, options);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int c = 0; c < 3; ++c)
            strip[(static_cast<size_t>(y) * strip_w + i * (w + kGap) + x) * 3 + c] =
                rgb[(static_cast<size_t>(y0 + y) * image.width + x0 + x) * 3 + c];
    }
    sylva::write_png_rgb8(argv[1], strip_w, h, strip);
  } catch (const std::exception& e) {
    fmt::print(stderr, "sylva_crop_strip: {}\n", e.what());
    return 2;
  }
  return 0;
}
