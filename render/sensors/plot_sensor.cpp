#include "render/sensors/plot_sensor.h"

#include "core/error.h"
#include "core/hash.h"
#include "render/band_channels.h"
#include "render/primitives/media.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fmt/core.h>

#include <cmath>

namespace sylva {

namespace {

// Samples per block: each block's sums are kept apart and added in block order (determinism).
constexpr int kBlock = 256;

// The plot's top plane: just above every piece of geometry.
float plot_top(const EmbreeScene& embree) {
  const Bounds3& b = embree.bounds();
  if (b.empty()) return 0.0f;
  return b.hi.z + 1e-3f * (1.0f + std::abs(b.hi.z));
}

void check_plot(const Scene& scene, const MeasureSettings& settings) {
  if (!scene.plot.defined) throw Error("the scene has no [plot]: the plot sensor needs its rectangle");
  if (settings.bands.empty()) throw Error("no bands to measure");
  if (settings.plot.samples < 1 || settings.plot.flux_samples < 1) throw Error("sample counts must be positive");
}

Vec3 plot_point(const PlotDesc& plot, float top, Pcg32& rng) {
  const Vec2 u = uniform2(rng);
  return Vec3(plot.lo.x + (plot.hi.x - plot.lo.x) * u.x, plot.lo.y + (plot.hi.y - plot.lo.y) * u.y, top);
}

template <class Body>
void run_blocks(int threads, size_t blocks, const Body& body) {
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] { tbb::parallel_for(size_t{0}, blocks, [&](size_t b) { body(b); }); });
}

// Per block and channel of the flux walk: Σy, Σy², and per term Σx, Σx², Σxy.
constexpr size_t kFluxStride = 2 + 3 * FluxTable::kTerms;

// The flux table from the per-block sums: per block and channel kFluxStride values, Σy, Σy² and per
// term Σx, Σx², Σxy (y = incident, x = the term's share), over n samples in `blocks` blocks.
FluxTable summarise_flux(const std::vector<double>& sums, size_t blocks, const std::vector<std::string>& channels,
                         int n) {
  constexpr int kT = FluxTable::kTerms;
  constexpr size_t kStride = kFluxStride;
  const size_t nc = channels.size();
  FluxTable table;
  table.channels = channels;
  table.samples = n;
  for (size_t c = 0; c < nc; ++c) {
    std::array<double, kStride> s{};
    for (size_t b = 0; b < blocks; ++b)
      for (size_t k = 0; k < kStride; ++k) s[k] += sums[(b * nc + c) * kStride + k];
    std::array<double, kT> mean{}, se{};
    if (s[0] > 0) {
      // Ratio estimator R = Σx / Σy; its variance by the delta method, var(x − R y) / (n ȳ²).
      const double ybar = s[0] / n;
      for (int t = 0; t < kT; ++t) {
        const double r = s[2 + 3 * t] / s[0];
        const double var = std::max(0.0, (s[3 + 3 * t] - 2 * r * s[4 + 3 * t] + r * r * s[1]) / std::max(1.0, n - 1.0));
        mean[t] = r;
        se[t] = std::sqrt(var / n) / ybar;
      }
    }
    table.mean.push_back(mean);
    table.se.push_back(se);
  }
  return table;
}

}  // namespace

std::vector<PlotView> principal_plane_views(float from_deg, float to_deg, float step_deg, float sun_azimuth_deg) {
  if (!(step_deg > 0) || !(to_deg >= from_deg) || std::abs(from_deg) > 89.9f || std::abs(to_deg) > 89.9f)
    throw Error("principal plane: expected from ≤ to within ±89.9° and a positive step");
  std::vector<PlotView> views;
  const int n = static_cast<int>(std::floor((to_deg - from_deg) / step_deg + 1e-4f)) + 1;
  for (int i = 0; i < n; ++i) {
    const float z = from_deg + static_cast<float>(i) * step_deg;
    const float azimuth = z < 0 ? sun_azimuth_deg : sun_azimuth_deg + 180.0f;
    views.push_back(PlotView{std::abs(z), std::fmod(azimuth + 720.0f, 360.0f), z});
  }
  return views;
}

BrfTable measure_brf(const Scene& scene, const EmbreeScene& embree, const MeasureSettings& settings) {
  check_plot(scene, settings);
  const Environment environment(scene.sun, scene.sky);
  const BandChannels channels(settings.bands, environment, settings.quantity);
  const Integrator integrator(scene, embree, environment, settings.integrator);
  const WavelengthSampler wavelengths(settings.bands);
  const float top = plot_top(embree);
  const size_t nc = channels.size(), nv = settings.plot.views.size();
  const int n = settings.plot.samples;
  const size_t blocks_per_view = static_cast<size_t>((n + kBlock - 1) / kBlock);
  // Per block: sum and sum of squares per channel.
  std::vector<double> sums(nv * blocks_per_view * 2 * nc, 0.0);
  run_blocks(settings.threads, nv * blocks_per_view, [&](size_t block) {
    const size_t view = block / blocks_per_view;
    const PlotView& v = settings.plot.views[view];
    const Vec3 dir = -sun_direction(v.azimuth_deg, 90.0f - v.zenith_deg);
    double* out = &sums[block * 2 * nc];
    const int first = static_cast<int>(block % blocks_per_view) * kBlock;
    uint64_t rays = 0;
    for (int s = first; s < std::min(n, first + kBlock); ++s) {
      Pcg32 rng(hash_ids(settings.seed, 0x6272665fu, view, static_cast<uint64_t>(s)));
      const Vec3 p = plot_point(scene.plot, top, rng);
      const SampledWavelengths wl = wavelengths.sample(rng.uniform(), rng.uniform());
      SampledSpectrum L = integrator.radiance(Ray{p, dir}, wl, rng, nullptr, rays);
      for (int i = 0; i < kLambdaCount; ++i)
        if (!std::isfinite(L[i])) L = SampledSpectrum(0.0f);
      for (size_t c = 0; c < nc; ++c) {
        const double x = channels.weigh(c, L, wl) * channels.scale[c];
        out[c] += x;
        out[nc + c] += x * x;
      }
    }
  });
  BrfTable table;
  table.channels = channels.names;
  table.views = settings.plot.views;
  table.samples = n;
  table.top_m = top;
  for (size_t view = 0; view < nv; ++view) {
    std::vector<double> s(2 * nc, 0.0);
    for (size_t b = 0; b < blocks_per_view; ++b)
      for (size_t k = 0; k < 2 * nc; ++k) s[k] += sums[(view * blocks_per_view + b) * 2 * nc + k];
    std::vector<double> mean(nc), se(nc);
    for (size_t c = 0; c < nc; ++c) {
      mean[c] = s[c] / n;
      const double var = n > 1 ? std::max(0.0, (s[nc + c] - n * mean[c] * mean[c]) / (n - 1.0)) : 0.0;
      se[c] = std::sqrt(var / n);
    }
    table.mean.push_back(std::move(mean));
    table.se.push_back(std::move(se));
  }
  return table;
}

FluxTable measure_flux(const Scene& scene, const EmbreeScene& embree, const MeasureSettings& settings) {
  check_plot(scene, settings);
  if (has_turbid_crowns(scene))
    throw Error("the flux budget follows surfaces only: the scene's turbid crowns are not supported");
  for (const Material& m : scene.materials)
    if (emits(m))
      throw Error("the flux budget follows the sun's and sky's light: emitting materials are not supported");
  const Environment environment(scene.sun, scene.sky);
  if (environment.empty()) throw Error("the flux budget needs a sun or a sky");
  const BandChannels channels(settings.bands, environment, Quantity::radiance);
  const Integrator integrator(scene, embree, environment, settings.integrator);
  const WavelengthSampler wavelengths(settings.bands);
  const float top = plot_top(embree);
  const size_t nc = channels.size();
  const int n = settings.plot.flux_samples;
  const size_t blocks = static_cast<size_t>((n + kBlock - 1) / kBlock);
  enum Term { kLeaves, kBark, kGround, kGroundDirect, kGroundTotal, kReflected, kClosure };
  constexpr int kT = FluxTable::kTerms;
  // Per block and channel: Σy, Σy², and per term Σx, Σx², Σxy (y = incident, x = the term's share).
  constexpr size_t kStride = kFluxStride;
  std::vector<double> sums(blocks * nc * kStride, 0.0);
  const auto category = [&](uint32_t material) {
    if (is_foliage(scene.materials[material])) return kLeaves;
    for (const uint32_t g : settings.plot.ground_materials)
      if (g == material) return kGround;
    return kBark;
  };
  run_blocks(settings.threads, blocks, [&](size_t block) {
    double* out = &sums[block * nc * kStride];
    const int first = static_cast<int>(block) * kBlock;
    for (int s = first; s < std::min(n, first + kBlock); ++s) {
      Pcg32 rng(hash_ids(settings.seed, 0x666c7578u, static_cast<uint64_t>(s)));
      const Vec3 p = plot_point(scene.plot, top, rng);
      const SampledWavelengths wl = wavelengths.sample(rng.uniform(), rng.uniform());
      const LightSample ls = integrator.sample_light(wl, rng);
      // The energy this path carries onto the plot's top plane: L cos θ / pdf per wavelength.
      SampledSpectrum incident(0.0f);
      if (ls.pdf > 0 && ls.wi.z > 0) incident = ls.radiance * (ls.wi.z / ls.pdf);
      std::array<SampledSpectrum, kT> x;
      x.fill(SampledSpectrum(0.0f));
      SampledSpectrum beta = incident;
      Ray ray{p, -ls.wi};
      for (int depth = 0; !is_black(beta) && depth < settings.integrator.max_depth; ++depth) {
        RayHit hit;
        if (!embree.intersect(ray, &hit)) {
          if (ray.direction.z > 0) x[kReflected] += beta;
          break;
        }
        // The camera paths' transport step (Integrator): the vertex, its BSDF and its continuation.
        const SurfaceVertex v = integrator.surface_vertex(ray, hit, wl);
        const Term where = category(v.ctx.material);
        if (where == kGround) {
          x[kGroundTotal] += beta;
          if (depth == 0) x[kGroundDirect] += beta;
        }
        x[where] += beta * (SampledSpectrum(1.0f) - v.bsdf.albedo());
        const Vec2 u_bsdf = uniform2(rng);
        float pdf = 0;
        if (!integrator.scatter(v, u_bsdf, rng.uniform(), beta, pdf, ray)) break;
        if (depth + 1 >= settings.integrator.rr_start_depth) {
          // Roulette on the throughput relative to the incident energy, as the integrator does.
          float rel = 0;
          for (int i = 0; i < kLambdaCount; ++i)
            if (incident[i] > 0) rel = std::max(rel, beta[i] / incident[i]);
          const float q = std::max(0.05f, 1.0f - rel);
          if (rng.uniform() < q) break;
          beta /= 1.0f - q;
        }
      }
      x[kClosure] = x[kLeaves] + x[kBark] + x[kGround] + x[kReflected];
      for (size_t c = 0; c < nc; ++c) {
        double* o = out + c * kStride;
        const double y = channels.weigh(c, incident, wl);
        o[0] += y;
        o[1] += y * y;
        for (int t = 0; t < kT; ++t) {
          const double xv = channels.weigh(c, x[t], wl);
          o[2 + 3 * t] += xv;
          o[3 + 3 * t] += xv * xv;
          o[4 + 3 * t] += xv * y;
        }
      }
    }
  });
  return summarise_flux(sums, blocks, channels.names, n);
}

}  // namespace sylva
