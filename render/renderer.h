#pragma once
// Rendering a Scene into a Film, and a Film into an Image (EXR channels).
//
// A render covers a region of the image and a range of sample indices; work is split into square
// tiles rendered in parallel with TBB. Every sample's random numbers depend on (seed, pixel, sample
// index) alone (core/sampler.h), and each pixel's samples are accumulated in order by one thread
// (render/film.h), so the result is bit-identical at any thread count, whether or not the render
// was interrupted and resumed, and when it is split into regions or sample ranges whose films are
// merged (Film::merge).

#include "core/band.h"
#include "core/image.h"
#include "core/progress.h"
#include "render/band_channels.h"
#include "render/embree_scene.h"
#include "render/film.h"
#include "render/integrator.h"
#include "render/scene.h"

#include <atomic>
#include <memory>
#include <vector>

namespace sylva {

struct RenderSettings {
  int width = 640;
  int height = 360;
  int spp = 64;  // samples per pixel to reach
  uint64_t seed = 1;
  // The pixel samples' random numbers (core/sampler.h): Owen-scrambled Sobol' points, or
  // independent PCG32 draws (every render before issue 41; `sampler = "independent"`).
  SamplerKind sampler = SamplerKind::kSobol;
  int threads = 0;  // 0 = all hardware threads
  int tile_size = 16;
  std::vector<Band> bands;  // at least one
  IntegratorSettings integrator;
  Quantity quantity = Quantity::radiance;
  // Also gather the denoiser's features and half-buffers (make_image; docs/denoise.md): more film
  // channels and one occlusion ray per camera path; the other channels keep their bits.
  bool features = false;
  // Also write "id.material" (make_image): the first hit's material index + 1, 0 for the sky. Off by
  // default, so the default EXR keeps its channels; the compare's local tests test each material's
  // pixels as a region (docs/compare.md, "Local tests").
  bool material_ids = false;
  // Embree's kernels (EmbreeIsa): at most AVX2 unless asked, so the bits are the same on every
  // processor with AVX2.
  EmbreeIsa isa = EmbreeIsa::kAvx2;
  bool progress = true;      // progress on stderr: a bar on a terminal, else periodic lines with an ETA
  ProgressSink on_progress;  // told the samples done and left (Progress), with or without a bar
  // Adaptive sampling (docs/sampling.md, "Adaptive sampling"): 0 = off; else the relative standard
  // error each pixel's mean should reach in every channel of noise_channels (every band channel if
  // empty). Every pixel takes pilot_spp samples (even, ≥ 4), then as many more as its estimated
  // error asks, up to spp. Renders in passes (progressive).
  float noise_threshold = 0;
  std::vector<std::string> noise_channels;
  int pilot_spp = 16;
  // Render in passes of doubling sample counts, every pixel reaching one count before any goes on to
  // the next, so a render stopped early (a time limit) has its samples spread over the whole image.
  // The same bits as one pass: each pixel's samples are still added in index order.
  bool progressive = false;
  // Stop after this many seconds of rendering (0 = none): RenderSession ends the render there as
  // complete, each pixel with the samples it has; implies progressive.
  double time_limit_s = 0;
  // Set asynchronously (e.g. by SIGINT) to stop early; every pixel keeps the samples it finished.
  const std::atomic<bool>* cancel = nullptr;
};

struct RenderStats {
  double seconds = 0;
  // Processor time the process spent during the call (user + system, every thread): the figure that
  // stays comparable on a machine shared with other jobs, where `seconds` stretches.
  double cpu_seconds = 0;
  uint64_t samples = 0;  // path samples added in this call
  uint64_t rays = 0;
  bool interrupted = false;
  EmbreeStats embree;
};

// What a render needs in memory beyond the scene description (docs/limits.md), before anything is
// allocated: the film (sum and sum of squares as doubles for each radiance and albedo channel, and a
// sample count per pixel), the output image (floats: mean, variance and albedo per radiance channel,
// depth, normal, position, four ids) with its preview, and the BVH (an estimate per unique triangle,
// leaf quad and leaf disc — each one Embree primitive, at most — measured on the shipped scenes; per
// unique grass curve (a strip of six quads in Embree); and per Embree instance, native or in the
// instance array: kNativeInstanceBytes, kArrayInstanceBytes).
struct MemoryEstimate {
  uint64_t film_bytes = 0, image_bytes = 0, bvh_bytes = 0;
  uint64_t total() const { return film_bytes + image_bytes + bvh_bytes; }
};
// Embree's BVH and the vertices it reads, measured by Embree's monitor plus the vertex arrays it
// shares with the scene (EmbreeStats::shared_vertex_bytes): 199 per leaf quad
// (bench/scenes/dense_grove.toml: 151 + 48); the default forest's 1.07 M triangles (most paired
// into quads) and 0.79 M leaf quads, 138 each on average.
inline constexpr uint64_t kBvhBytesPerPrimitive = 220;
// Measured by Embree's monitor: about 1 200 per blade (golden/scenes/grass_terrain.toml, 400 blades).
inline constexpr uint64_t kBvhBytesPerCurve = 1300;
MemoryEstimate estimate_render_memory(const Scene& scene, const RenderSettings& settings);

// The BVH build for a whole render (every chunk, rank and resumed pass of it builds the same, so
// their samples agree bit for bit).
BvhBuild bvh_build_for(const RenderSettings& settings);

class Renderer {
 public:
  // Renders `scene` through `embree`, built from that same scene by the caller and shared with any
  // other pass over it. Both must outlive the renderer.
  Renderer(const Scene& scene, const EmbreeScene& embree, RenderSettings settings);
  // Convenience for a single pass: builds (and owns) the Embree scene. `scene` must outlive it.
  Renderer(const Scene& scene, RenderSettings settings);
  // Test seam: deliberate transport faults in the integrator (render/testing/faults.h); build
  // `embree` with the same faults to include the occlusion-filter fault.
  Renderer(const Scene& scene, const EmbreeScene& embree, RenderSettings settings, const TransportFaults& faults);
  ~Renderer();

  // The whole image, settings.width × settings.height.
  PixelRegion image_region() const { return PixelRegion::whole(settings_.width, settings_.height); }
  // A film for the whole image, samples from 0 on.
  Film make_film() const;
  // A film for `window` (inside the image) holding samples from `first_sample` on: a tile or a
  // sample chunk of a split render, merged later with Film::merge.
  Film make_film(const PixelRegion& window, uint32_t first_sample) const;
  // The channels of this renderer's films: each band channel's Σ and Σ², plus the denoiser's
  // features and half-buffers when settings.features.
  int film_channels() const;

  // Adds samples to every pixel of the film's window until it has settings.spp (or cancel is set).
  // Equivalent to render(film, film.window(), {film.first_sample(), settings.spp}).
  RenderStats render(Film& film);
  // Adds samples of indices in `samples` to every pixel of `region` (inside the film's window):
  // each pixel continues from its next sample, first_sample() + count(x, y) — samples it already
  // has are not rendered again — up to samples.end. Throws sylva::Error if a pixel's next sample
  // lies before samples.first (a gap: its samples would not be in index order). If cancel is set,
  // stops between pixels; every pixel keeps whole samples, in order, so the film can be resumed.
  RenderStats render(Film& film, const PixelRegion& region, SampleRange samples);

  // An image of the film's window (the whole image for make_film()). Channels: each band's
  // channels (mean radiance, or reflectance factor: settings.quantity), "var.<C>" (variance of the mean), the albedo
  // AOV per band channel
  // ("albedo.<C>"), and the first-hit AOVs from a ray through each pixel centre: "Z" (camera-space
  // depth in m; 1e10 for the sky), "N.X/N.Y/N.Z" (world geometric normal facing the camera),
  // "P.X/P.Y/P.Z" (world position of the hit, m; for the sky the point 1e10 m along the ray),
  // "id.instance" (instance index + 1, 0 = sky), "id.object", "id.class" (Instance::class_id, 0 = sky)
  // and "id.variant" (Instance::variant_id, 0 = sky or none); with settings.material_ids,
  // "id.material" (the hit's material index in Scene::materials + 1, 0 = sky).
  // With settings.features, after those, the denoiser's channels, each a mean over the pixel's
  // samples (docs/denoise.md): "even.<C>" and "odd.<C>" (the means of the even- and odd-indexed
  // samples of each band channel), "feature.albedo.<C>" (the albedo AOV with the sky counted as 1),
  // "feature.N.X/Y/Z" (first-hit shading normal facing the camera; 0 for the sky), "feature.Z"
  // (camera-space depth, m; 0 for the sky), "feature.sun" (the first hit sees the sun's centre;
  // 1 for the sky), "feature.class.leaf/bark/ground/sky" (fractions of the samples, FeatureClass),
  // and "var.feature.<F>" (variance of the mean) of the normal, depth and sun features.
  Image make_image(const Film& film) const;

  const RenderSettings& settings() const { return settings_; }
  const EmbreeScene& embree() const { return embree_; }
  const EmbreeStats& embree_stats() const { return embree_.stats(); }
  const std::vector<std::string>& radiance_channels() const { return channels_.names; }
  // Per radiance channel: the band-weighted horizontal irradiance E_c (channel_irradiance).
  const std::vector<float>& irradiance() const { return channels_.irradiance; }

 private:
  Renderer(const Scene& scene, std::unique_ptr<EmbreeScene> owned, const EmbreeScene* shared, RenderSettings settings,
           const TransportFaults& faults);
  void check_film(const Film& film) const;
  // Renders samples [first, end) of pixel (x, y): of its one sequence (stream kAllSamples: sample
  // index = position in the sequence) or of adaptive sampling's stream 0 or 1 (sample j of the stream).
  static constexpr int kAllSamples = -1;
  void render_pixel(Film& film, int x, int y, int stream, uint32_t first, uint32_t end, uint64_t& rays) const;
  // One path's radiance and first hit, weighted into the channels and added to pixel (x, y): sample
  // `index` of `stream`.
  void add_sample(Film& film, int x, int y, int stream, uint32_t index, const SampledWavelengths& wl, SampledSpectrum L,
                  const FirstHit& first, const Vec3& camera_direction) const;
  // The feature values of one sample (settings.features) after its band and albedo values.
  void feature_values(const FirstHit& first, const Vec3& camera_direction, float* features) const;
  // Adaptive sampling (settings.noise_threshold > 0; renderer_adaptive.cpp).
  bool adaptive() const { return settings_.noise_threshold > 0; }
  // The film holds each band channel's sum over the even samples (stream 0 when adaptive).
  bool has_even_channels() const { return settings_.features || adaptive(); }
  bool progressive() const { return settings_.progressive || settings_.time_limit_s > 0; }
  int even_channel(size_t c) const { return static_cast<int>(2 * channels_.size() + c); }
  // Stream 0's sample count of pixel (x, y), and the samples stream `stream` should reach: decided
  // from the other stream's pilot samples alone (docs/sampling.md).
  uint32_t stream0_count(const Film& film, int x, int y) const;
  uint32_t stream_target(const Film& film, int x, int y, int stream) const;
  // The pixel mean of band channel c, and its variance: (mean₀ + mean₁)/2 of the two streams when
  // adaptive, else the mean over all samples.
  double channel_mean(const Film& film, int x, int y, int c) const;
  double channel_variance_of_mean(const Film& film, int x, int y, int c) const;
  RenderStats render_passes(Film& film, const PixelRegion& region, SampleRange samples);
  // make_image's feature channels of pixel (x, y), from channel `first_channel` of the image on.
  void write_features(Image& image, const Film& film, int x, int y, int first_channel) const;

  const Scene& scene_;
  RenderSettings settings_;
  std::unique_ptr<EmbreeScene> owned_embree_;  // only for the convenience constructor
  const EmbreeScene& embree_;
  Environment environment_;
  std::unique_ptr<Integrator> integrator_;
  Camera camera_;
  WavelengthSampler wavelengths_;
  BandChannels channels_;  // the radiance channels, band after band
  Vec3 forward_{0.0f};     // the camera's viewing direction (depth feature)
  // The radiance channels in blocks of four, the last padded with zeros: add_sample weighs a
  // sample into four channels per vector operation (bench/README.md, "Four at a time").
  size_t channel_blocks_ = 0;
  // w_c(λ) per radiance channel on the 1 nm grid, the channels interleaved ([grid index][block]):
  // a sample's weights for all channels at one wavelength are one or two cache lines, not one each.
  std::vector<Vec4> interleaved_weights_;
  // Per block of channels: 1, or π / E_c for reflectance; kLambdaCount · ∫ w_c dλ (1 where the
  // integral is 0, which normalises the albedo AOV) and whether it is not 0.
  std::vector<Vec4> scale_blocks_, albedo_norm_blocks_;
  std::vector<glm::bvec4> has_albedo_blocks_;
  // Adaptive sampling's film channels after the others: stream 0's sample count, then per noise
  // channel its sums over the pilot samples of stream 0 and of both streams. noise_channels_: the
  // band channels the threshold applies to; noise_floor_: the squared radiance (or reflectance)
  // below which a pixel's error counts as absolute, 1 % of a white Lambertian's.
  int adaptive_base_ = 0;
  std::vector<int> noise_channels_;
  std::vector<double> noise_floor_;
};

}  // namespace sylva
