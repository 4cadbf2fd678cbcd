// `sylva denoise IN.exr -o OUT.exr`: the feature-guided denoiser (denoise/denoise_image.h) on a
// render made with --features (or a merged split render of one): the denoised beauty replaces the
// noisy one, which is kept as noisy.<C>; every other channel is kept.

#include "app/commands.h"
#include "core/error.h"
#include "core/image.h"
#include "core/output_paths.h"
#include "denoise/denoise_image.h"
#include "pipeline/outputs.h"

#include <fmt/core.h>

namespace sylva {

namespace {

struct DenoiseOptions {
  std::string input, exr, png;
  float exposure = 0.0f;
  DenoiseSettings settings;
  bool quiet = false;
};

int run_denoise(const DenoiseOptions& opt) {
  check_outputs({{"-o", opt.exr}, {"--png", opt.png}}, {opt.input});
  const Image noisy = read_exr(opt.input);
  DenoiseStats stats;
  const Image clean = denoise_image(noisy, opt.settings, &stats);
  write_exr(opt.exr, clean);
  if (!opt.png.empty()) {
    PreviewOptions preview;
    if (clean.find_channel("R") < 0) {
      const std::string grey = denoisable_channels(noisy).front();
      preview.channels = {grey, grey, grey};
    }
    preview.exposure_ev = opt.exposure + auto_exposure_ev(clean, preview.channels);
    write_png_preview(opt.png, clean, preview);
  }
  if (!opt.quiet)
    fmt::print(stderr, "denoised {} channel(s) of {} into {} in {:.2f} s\n", denoisable_channels(noisy).size(),
               opt.input, opt.exr, stats.seconds);
  return 0;
}

}  // namespace

CommandRun add_denoise_command(CLI::App& parent) {
  auto opt = std::make_shared<DenoiseOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "denoise", "Denoise a render made with --features: R, G, B and every band replaced, noisy.* kept");
  cmd->add_option("input", opt->input, "The noisy EXR (sylva render --features, or sylva merge of one)")->required();
  cmd->add_option("-o,--output", opt->exr, "Output EXR (written atomically)")->required();
  cmd->add_option("--png", opt->png,
                  "PNG preview of the denoised visible band (Standard view, median luminance at 18 % grey)");
  cmd->add_option("--exposure", opt->exposure, "Preview exposure offset in stops, added to the automatic exposure")
      ->check(kFiniteNumber & CLI::Range(-64.0, 64.0));
  cmd->add_option("--threads", opt->settings.threads, "Worker threads (0 = all)")->check(CLI::Range(0, 4096));
  cmd->add_flag("-q,--quiet", opt->quiet, "No summary");
  return [opt] { return run_denoise(*opt); };
}

}  // namespace sylva
