#include "pipeline/measure.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/output_paths.h"
#include "render/embree_scene.h"

#include <fmt/core.h>
#include <fmt/ostream.h>

#include <chrono>

namespace sylva {

namespace {

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

void write_brf(const std::filesystem::path& path, const SceneFile& file, const MeasureSettings& s, const BrfTable& t) {
  write_file_atomic(path, [&](std::ostream& out) {
    write_header(out, file, s, s.quantity == Quantity::reflectance ? "BRF" : "mean radiance", t.samples);
    fmt::print(out, "# rays start on the plot's top plane z = {:.6g} m; _se = Monte Carlo standard error\n", t.top_m);
    fmt::print(out, "view_zenith_deg,view_azimuth_deg,signed_zenith_deg");
    for (const std::string& c : t.channels) fmt::print(out, ",{},{}_se", c, c);
    fmt::print(out, "\n");
    for (size_t v = 0; v < t.views.size(); ++v) {
      fmt::print(out, "{:g},{:g},{:g}", t.views[v].zenith_deg, t.views[v].azimuth_deg, t.views[v].label_deg);
      for (size_t c = 0; c < t.channels.size(); ++c) fmt::print(out, ",{:.7g},{:.3g}", t.mean[v][c], t.se[v][c]);
      fmt::print(out, "\n");
    }
  });
}

void write_flux(const std::filesystem::path& path, const SceneFile& file, const MeasureSettings& s,
                const FluxTable& t) {
  write_file_atomic(path, [&](std::ostream& out) {
    write_header(out, file, s, "flux budget (fractions of the incident energy)", t.samples);
    fmt::print(out, "channel");
    for (const char* name : FluxTable::kNames) fmt::print(out, ",{},{}_se", name, name);
    fmt::print(out, "\n");
    for (size_t c = 0; c < t.channels.size(); ++c) {
      fmt::print(out, "{}", t.channels[c]);
      for (int k = 0; k < FluxTable::kTerms; ++k) fmt::print(out, ",{:.7g},{:.3g}", t.mean[c][k], t.se[c][k]);
      fmt::print(out, "\n");
    }
  });
}

}  // namespace

MeasureResult measure_scene(const MeasureCallOptions& options, RenderObserver& observer) {
  if (options.brf.empty() && options.flux.empty()) throw Error("measure: give --brf FILE, --flux FILE or both");
  check_outputs({{"--brf", options.brf}, {"--flux", options.flux}}, {options.request.source.file});
  observer.on_phase(RenderPhase::loading);
  RenderRequest request = options.request;
  if (request.quantity.empty()) request.quantity = "reflectance";
  const RenderJob job = prepare_render(request);
  check_outputs({{"--brf", options.brf}, {"--flux", options.flux}}, job.file.inputs);
  const Scene& scene = job.file.scene;
  const std::string name = options.request.source.label();
  if (!scene.plot.defined) throw Error(name + ": the scene has no [plot] section to measure");
  MeasureSettings s;
  s.plot = job.file.plot;
  if (options.samples > 0) s.plot.samples = options.samples;
  if (options.flux_samples > 0) s.plot.flux_samples = options.flux_samples;
  s.bands = job.settings.bands;
  s.integrator = job.settings.integrator;
  s.quantity = job.settings.quantity;
  s.seed = job.settings.seed;
  s.threads = job.settings.threads;
  if (!options.brf.empty() && s.plot.views.empty())
    throw Error(name + ": --brf needs view directions: [plot] views or principal_plane");
  const EmbreeScene embree(scene, BvhBuild::kThorough, job.settings.isa);
  observer.on_phase(RenderPhase::rendering);
  MeasureResult result;
  if (!options.brf.empty()) {
    const auto start = std::chrono::steady_clock::now();
    result.brf = measure_brf(scene, embree, s);
    write_brf(options.brf, job.file, s, *result.brf);
    result.brf_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (!options.flux.empty()) {
    const auto start = std::chrono::steady_clock::now();
    result.flux = measure_flux(scene, embree, s);
    write_flux(options.flux, job.file, s, *result.flux);
    result.flux_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return result;
}

}  // namespace sylva
