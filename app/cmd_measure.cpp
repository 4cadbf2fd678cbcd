// `sylva measure`: the plot sensor (docs/radiometry.md, "Plot sensor"): the BRF (or mean
// radiance) of a scene's [plot] for its view directions, and the plot's flux budget, as CSV.

#include "app/cli_observer.h"
#include "app/commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/output_paths.h"
#include "pipeline/scene_request.h"
#include "render/embree_scene.h"
#include "render/sensors/plot_sensor.h"

#include <fmt/core.h>
#include <fmt/ostream.h>

#include <chrono>
#include <memory>

namespace sylva {

namespace {

struct MeasureOptions {
  RenderRequest request;
  std::string brf, flux;
  int samples = 0, flux_samples = 0;
};

void write_header(std::ostream& out, const SceneFile& file, const MeasureSettings& s, const char* what, int samples) {
  std::string bands;
  for (const Band& b : s.bands) bands += (bands.empty() ? "" : " ") + b.name;
  fmt::print(out, "# sylva {} {}: scene {} (hash {}), bands {}, seed {}, {} samples, max_depth {}\n", SYLVA_VERSION,
             what, file.path.filename().string(), file.content_hash, bands, s.seed, samples, s.integrator.max_depth);
  const PlotDesc& p = file.scene.plot;
  fmt::print(out, "# plot x [{:g}, {:g}] y [{:g}, {:g}] m, {}; sun azimuth {:g} elevation {:g} deg\n", p.lo.x, p.hi.x,
             p.lo.y, p.hi.y, p.cyclic ? "cyclic" : "not cyclic", file.scene.sun.azimuth_deg,
             file.scene.sun.elevation_deg);
}

}  // namespace

CommandRun add_measure_command(CLI::App& parent) {
  auto opt = std::make_shared<MeasureOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "measure",
      "Plot sensor: the BRF (or mean radiance) of the scene's [plot] per view direction and its flux budget, as CSV "
      "with standard errors (docs/radiometry.md)");
  RenderRequest& req = opt->request;
  cmd->add_option("scene", req.source.file, "Scene file (TOML) with a [plot] section")->required();
  cmd->add_option("--brf", opt->brf, "Output CSV: per view direction, each band channel's mean and standard error");
  cmd->add_option("--flux", opt->flux, "Output CSV: per band channel, the flux fractions and standard errors");
  cmd->add_option("--samples", opt->samples, "Rays per view direction (default: [plot] samples)")
      ->check(CLI::Range(1, 1 << 30));
  cmd->add_option("--flux-samples", opt->flux_samples, "Light paths of the flux budget (default: [plot] flux_samples)")
      ->check(CLI::Range(1, 1 << 30));
  cmd->add_option("--threads", req.threads, "Worker threads (0 = all)")->check(CLI::Range(0, 4096));
  cmd->add_option("--seed", req.seed, "Random seed")->check(kUint64 & CLI::Range(int64_t{0}, INT64_MAX));
  cmd->add_option("--bands", req.bands, "Comma-separated bands, e.g. S2A_B4,S2A_B8 (default: the scene's)");
  cmd->add_option("--max-depth", req.max_depth, "Maximum path depth")->check(CLI::Range(1, 1024));
  cmd->add_option("--quantity", req.quantity, "BRF columns as reflectance (factor, the default) or radiance")
      ->check(CLI::IsMember({"radiance", "reflectance"}));
  cmd->add_option("--isa", req.isa, "Embree's kernels, at most (as sylva render --isa; default avx2)")
      ->check(CLI::IsMember(embree_isa_names()));
  add_set_option(cmd, req.overrides);
  return [opt] {
    if (opt->brf.empty() && opt->flux.empty()) throw Error("measure: give --brf FILE, --flux FILE or both");
    RenderRequest request = opt->request;
    if (request.quantity.empty()) request.quantity = "reflectance";
    const RenderJob job = prepare_render(request);
    check_outputs({{"--brf", opt->brf}, {"--flux", opt->flux}}, job.file.inputs);
    const Scene& scene = job.file.scene;
    if (!scene.plot.defined) throw Error(job.file.path.string() + ": the scene has no [plot] section to measure");
    MeasureSettings s;
    s.plot = job.file.plot;
    if (opt->samples > 0) s.plot.samples = opt->samples;
    if (opt->flux_samples > 0) s.plot.flux_samples = opt->flux_samples;
    s.bands = job.settings.bands;
    s.integrator = job.settings.integrator;
    s.quantity = job.settings.quantity;
    s.seed = job.settings.seed;
    s.threads = job.settings.threads;
    if (!opt->brf.empty() && s.plot.views.empty())
      throw Error(job.file.path.string() + ": --brf needs view directions: [plot] views or principal_plane");
    const EmbreeScene embree(scene, BvhBuild::kThorough, job.settings.isa);
    if (!opt->brf.empty()) {
      const auto start = std::chrono::steady_clock::now();
      const BrfTable t = measure_brf(scene, embree, s);
      write_file_atomic(opt->brf, [&](std::ostream& out) {
        write_header(out, job.file, s, s.quantity == Quantity::reflectance ? "BRF" : "mean radiance", t.samples);
        fmt::print(out, "# rays start on the plot's top plane z = {:.6g} m; _se = Monte Carlo standard error\n",
                   t.top_m);
        fmt::print(out, "view_zenith_deg,view_azimuth_deg,signed_zenith_deg");
        for (const std::string& c : t.channels) fmt::print(out, ",{},{}_se", c, c);
        fmt::print(out, "\n");
        for (size_t v = 0; v < t.views.size(); ++v) {
          fmt::print(out, "{:g},{:g},{:g}", t.views[v].zenith_deg, t.views[v].azimuth_deg, t.views[v].label_deg);
          for (size_t c = 0; c < t.channels.size(); ++c) fmt::print(out, ",{:.7g},{:.3g}", t.mean[v][c], t.se[v][c]);
          fmt::print(out, "\n");
        }
      });
      fmt::print(stderr, "measure: {} views x {} rays in {:.1f} s -> {}\n", t.views.size(), t.samples,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), opt->brf);
    }
    if (!opt->flux.empty()) {
      const auto start = std::chrono::steady_clock::now();
      const FluxTable t = measure_flux(scene, embree, s);
      write_file_atomic(opt->flux, [&](std::ostream& out) {
        write_header(out, job.file, s, "flux budget (fractions of the incident energy)", t.samples);
        fmt::print(out, "channel");
        for (const char* name : FluxTable::kNames) fmt::print(out, ",{},{}_se", name, name);
        fmt::print(out, "\n");
        for (size_t c = 0; c < t.channels.size(); ++c) {
          fmt::print(out, "{}", t.channels[c]);
          for (int k = 0; k < FluxTable::kTerms; ++k) fmt::print(out, ",{:.7g},{:.3g}", t.mean[c][k], t.se[c][k]);
          fmt::print(out, "\n");
        }
      });
      fmt::print(stderr, "measure: flux budget of {} paths in {:.1f} s -> {}\n", t.samples,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), opt->flux);
    }
    return 0;
  };
}

}  // namespace sylva
