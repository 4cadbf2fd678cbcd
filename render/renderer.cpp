#include "render/renderer.h"

#include "core/error.h"
#include "core/progress.h"

#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fmt/core.h>

#include <chrono>

#include <sys/resource.h>

namespace sylva {

namespace {

// The film's feature channels after each band channel's radiance and albedo (settings.features):
// the even-sample beauty per band channel, then these.
enum FeatureSlot { kNormalX, kNormalY, kNormalZ, kDepth, kSun, kLeaf, kBark, kGround, kSky, kFeatureSlots };
constexpr const char* kFeatureNames[kFeatureSlots] = {"N.X",        "N.Y",        "N.Z",          "Z",        "sun",
                                                      "class.leaf", "class.bark", "class.ground", "class.sky"};
constexpr int kFeaturesWithVariance = kLeaf;  // normal, depth and sun
static_assert(static_cast<int>(FeatureClass::kLeaf) == 1 && static_cast<int>(FeatureClass::kBark) == 2 &&
              static_cast<int>(FeatureClass::kGround) == 3);

// The film's channels: each band channel's radiance and albedo; each one's even-sample sum (with the
// features or adaptive sampling); the features; adaptive sampling's stream count and two pilot sums
// per noise channel (Renderer::adaptive_base_).
int adaptive_base(size_t band_channels, bool features) {
  return static_cast<int>(3 * band_channels + (features ? kFeatureSlots : 0));
}
int film_channels(size_t band_channels, bool features, size_t noise_channels) {
  if (noise_channels > 0) return adaptive_base(band_channels, features) + 1 + 2 * static_cast<int>(noise_channels);
  return static_cast<int>(2 * band_channels + (features ? band_channels + kFeatureSlots : 0));
}

// The band channels adaptive sampling watches: `names` (every channel if empty), as indices.
std::vector<int> noise_channel_indices(const std::vector<std::string>& names, const BandChannels& channels) {
  std::vector<int> out;
  if (names.empty()) {
    for (size_t c = 0; c < channels.size(); ++c) out.push_back(static_cast<int>(c));
    return out;
  }
  for (const std::string& n : names) {
    const auto it = std::find(channels.names.begin(), channels.names.end(), n);
    if (it == channels.names.end()) {
      std::string known;
      for (const auto& c : channels.names) known += (known.empty() ? "" : ", ") + c;
      throw Error(fmt::format("noise channel '{}' is not a channel of this render (its channels: {})", n, known));
    }
    out.push_back(static_cast<int>(it - channels.names.begin()));
  }
  return out;
}

}  // namespace

Renderer::Renderer(const Scene& scene, const EmbreeScene& embree, RenderSettings settings)
    : Renderer(scene, nullptr, &embree, std::move(settings), TransportFaults{}) {}

Renderer::Renderer(const Scene& scene, RenderSettings settings)
    : Renderer(scene, std::make_unique<EmbreeScene>(scene), nullptr, std::move(settings), TransportFaults{}) {}

Renderer::Renderer(const Scene& scene, const EmbreeScene& embree, RenderSettings settings,
                   const TransportFaults& faults)
    : Renderer(scene, nullptr, &embree, std::move(settings), faults) {}

Renderer::Renderer(const Scene& scene, std::unique_ptr<EmbreeScene> owned, const EmbreeScene* shared,
                   RenderSettings settings, const TransportFaults& faults)
    : scene_(scene),
      settings_(std::move(settings)),
      owned_embree_(std::move(owned)),
      embree_(shared ? *shared : *owned_embree_) {
  if (&embree_.scene() != &scene_) throw Error("the Embree scene was built from another scene");
  if (settings_.width <= 0 || settings_.height <= 0) throw Error("resolution must be positive");
  if (settings_.spp <= 0) throw Error("samples per pixel must be positive");
  if (settings_.bands.empty()) throw Error("no bands to render");
  if (settings_.integrator.max_depth < 1) throw Error("maximum depth must be at least 1");
  if (settings_.integrator.light_samples < 1 || settings_.integrator.light_samples > kMaxLightSamples)
    throw Error(
        fmt::format("light samples must be 1 to {}; got {}", kMaxLightSamples, settings_.integrator.light_samples));
  if (band_channel_count(settings_.bands) > 64) throw Error("too many band channels (at most 64)");
  if (!(settings_.noise_threshold >= 0 && settings_.noise_threshold < 1))
    throw Error(
        fmt::format("noise threshold {} is not in [0, 1) (a relative error, e.g. 0.02)", settings_.noise_threshold));
  if (adaptive() && (settings_.pilot_spp < 4 || settings_.pilot_spp % 2 != 0 || settings_.pilot_spp > settings_.spp))
    throw Error(fmt::format("pilot samples per pixel must be even, at least 4 and at most spp ({}); got {}",
                            settings_.spp, settings_.pilot_spp));
  environment_ = Environment(scene_.sun, scene_.sky);
  channels_ = BandChannels(settings_.bands, environment_, settings_.quantity);
  // After the channels' irradiance: the fault changes the radiance, not the recorded normalisation.
  if (faults.sky_horizon_gain != 1.0f)
    environment_.inject_horizon_fault(faults.sky_horizon_gain, faults.sky_horizon_elevation_deg);
  if (adaptive()) {
    noise_channels_ = noise_channel_indices(settings_.noise_channels, channels_);
    for (const int c : noise_channels_) {
      const double white = channels_.irradiance[static_cast<size_t>(c)] / kPi * channels_.scale[static_cast<size_t>(c)];
      noise_floor_.push_back(white > 0 ? sqr(0.01 * white) : 1e-20);
    }
    adaptive_base_ = adaptive_base(channels_.size(), settings_.features);
  }
  const std::vector<const DenseSpectrum*>& weights = channels_.weights;
  channel_blocks_ = (weights.size() + 3) / 4;
  interleaved_weights_.assign(static_cast<size_t>(kLambdaSamples) * channel_blocks_, Vec4(0.0f));
  for (int i = 0; i < kLambdaSamples; ++i)
    for (size_t c = 0; c < weights.size(); ++c)
      interleaved_weights_[i * channel_blocks_ + c / 4][static_cast<int>(c % 4)] = (*weights[c])[i];
  scale_blocks_.assign(channel_blocks_, Vec4(0.0f));
  albedo_norm_blocks_.assign(channel_blocks_, Vec4(1.0f));
  has_albedo_blocks_.assign(channel_blocks_, glm::bvec4(false));
  for (size_t c = 0; c < channels_.size(); ++c) {
    const int lane = static_cast<int>(c % 4);
    scale_blocks_[c / 4][lane] = channels_.scale[c];
    const auto weight_integral = static_cast<float>(weights[c]->integral());  // ∫ w_c dλ, for the albedo AOV
    if (weight_integral != 0) {
      albedo_norm_blocks_[c / 4][lane] = kLambdaCount * weight_integral;
      has_albedo_blocks_[c / 4][lane] = true;
    }
  }
  IntegratorSettings integrator = settings_.integrator;
  integrator.first_hit_features = settings_.features;
  integrator_ = std::make_unique<Integrator>(scene_, embree_, environment_, integrator, faults);
  forward_ = glm::normalize(scene_.camera.target - scene_.camera.position);
  camera_ = Camera(scene_.camera, settings_.width, settings_.height);
  wavelengths_ = WavelengthSampler(settings_.bands);
}

Renderer::~Renderer() = default;

MemoryEstimate estimate_render_memory(const Scene& scene, const RenderSettings& settings) {
  uint64_t channels = 0;
  for (const Band& b : settings.bands) channels += b.channels.size();
  const uint64_t pixels = static_cast<uint64_t>(settings.width) * static_cast<uint64_t>(settings.height);
  uint64_t primitives = 0, curves = 0;
  for (const Prototype& p : scene.prototypes) {
    primitives += p.triangles.triangles.size() + p.leaves.size() + p.discs.size();
    curves += p.curves.size();
  }
  const uint64_t copies = scene.instances.size() * (scene.plot.defined && scene.plot.cyclic ? 9 : 1);
  MemoryEstimate m;
  const size_t noise =
      settings.noise_threshold > 0 ? (settings.noise_channels.empty() ? channels : settings.noise_channels.size()) : 0;
  m.film_bytes =
      pixels * (static_cast<uint64_t>(film_channels(channels, settings.features, noise)) * 2 * sizeof(double) +
                sizeof(uint32_t));
  m.image_bytes = pixels * ((3 * channels + 8) * sizeof(float) + 3 * sizeof(float) + 3);
  m.bvh_bytes = primitives * kBvhBytesPerPrimitive + curves * kBvhBytesPerCurve +
                copies * (uses_instance_array(scene) ? kArrayInstanceBytes : kNativeInstanceBytes);
  return m;
}

Film Renderer::make_film() const { return make_film(image_region(), 0); }

int Renderer::film_channels() const {
  return sylva::film_channels(channels_.size(), settings_.features, noise_channels_.size());
}

Film Renderer::make_film(const PixelRegion& window, uint32_t first_sample) const {
  return Film(settings_.width, settings_.height, film_channels(), window, first_sample);
}

void Renderer::check_film(const Film& film) const {
  if (film.width() != settings_.width || film.height() != settings_.height || film.channels() != film_channels())
    throw Error("film does not match the render settings");
}

void Renderer::render_pixel(Film& film, int x, int y, int stream, uint32_t first, uint32_t end, uint64_t& rays) const {
  const uint64_t pixel_id =
      static_cast<uint64_t>(y) * static_cast<uint64_t>(settings_.width) + static_cast<uint64_t>(x);
  // The pixel's paths a batch at a time (Integrator::trace_paths): a pixel's camera rays and first
  // shadow rays, nearly alike, follow each other through the same BVH nodes.
  constexpr int kBatch = 8;
  static_assert(kBatch <= Integrator::kMaxPaths);
  Pcg32 rngs[kBatch];
  PathSampler samplers[kBatch];
  FirstHit firsts[kBatch];
  PathState paths[kBatch];
  Vec3 directions[kBatch];
  for (uint32_t batch = first; batch < end; batch += kBatch) {
    const int n = static_cast<int>(std::min<uint32_t>(kBatch, end - batch));
    for (int k = 0; k < n; ++k) {
      PathSampler& sampler = samplers[k];
      const uint32_t index = batch + static_cast<uint32_t>(k);
      if (stream == kAllSamples)
        sampler.start(settings_.sampler, rngs[k], settings_.seed, pixel_id, index);
      else
        sampler.start_stream(settings_.sampler, rngs[k], settings_.seed, pixel_id, static_cast<uint32_t>(stream),
                             index);
      const Vec2 film_pos = Vec2(static_cast<float>(x), static_cast<float>(y)) + sampler.get2d(SampleDim::kPixel);
      const Vec2 lens = sampler.get2d(SampleDim::kLens);
      const SampledWavelengths wl =
          wavelengths_.sample(sampler.get1d(SampleDim::kWavelength), sampler.get1d(SampleDim::kHero));
      firsts[k] = FirstHit{};
      const Ray ray = camera_.generate_ray(film_pos, lens);
      directions[k] = ray.direction;
      paths[k].start(ray, wl, sampler, &firsts[k]);
    }
    integrator_->trace_paths({paths, static_cast<size_t>(n)}, rays);
    for (int k = 0; k < n; ++k)
      add_sample(film, x, y, stream, batch + static_cast<uint32_t>(k), paths[k].wl, paths[k].L, firsts[k],
                 directions[k]);
  }
}

void Renderer::add_sample(Film& film, int x, int y, int stream, uint32_t index, const SampledWavelengths& wl,
                          SampledSpectrum L, const FirstHit& first, const Vec3& camera_direction) const {
  // A non-finite radiance never reaches the film; such a sample counts as black.
  bool finite = true;
  for (int i = 0; i < kLambdaCount; ++i) finite &= std::isfinite(L[i]);
  if (!finite) L = SampledSpectrum(0.0f);
  // DenseSpectrum::eval of each channel's weight, on the interleaved table, four channels at a
  // time: each channel's sums in the same order as channel by channel (same bits).
  const size_t nb = channel_blocks_;
  const GridPositions g = grid_positions(wl);
  Vec4 v[16], a[16];  // at most 64 channels (the constructor checks)
  for (size_t b = 0; b < nb; ++b) v[b] = a[b] = Vec4(0.0f);
  for (int i = 0; i < kLambdaCount; ++i) {
    const Vec4* lo = &interleaved_weights_[static_cast<size_t>(g.index[i]) * nb];
    const Vec4* hi = lo + nb;
    const Vec4 fi(g.fraction[i]), pdf(wl.pdf[i]), li(L[i]), ai(first.albedo[i]);
    for (size_t b = 0; b < nb; ++b) {
      const Vec4 w = (lo[b] + fi * (hi[b] - lo[b])) / pdf;
      v[b] += li * w;
      a[b] += ai * w;
    }
  }
  const size_t nc = channels_.size();
  float values[3 * 64 + kFeatureSlots + 1 + 2 * 64];
  for (size_t b = 0; b < nb; ++b) {
    const Vec4 vb = v[b] / static_cast<float>(kLambdaCount) * scale_blocks_[b];
    const Vec4 ab = a[b] / albedo_norm_blocks_[b];
    for (int k = 0; k < 4 && 4 * b + k < nc; ++k) {
      values[4 * b + k] = vb[k];
      values[nc + 4 * b + k] = select(has_albedo_blocks_[b][k], ab[k], 0.0f);
    }
  }
  // The half-buffers: the sample's beauty in the even channel when it is even (an even index of the
  // pixel's sequence, or stream 0), else 0; the odd half is the whole minus the even.
  const bool even = stream == kAllSamples ? index % 2 == 0 : stream == 0;
  if (has_even_channels())
    for (size_t c = 0; c < nc; ++c) values[even_channel(c)] = even ? values[c] : 0.0f;
  if (settings_.features) feature_values(first, camera_direction, values + 3 * nc);
  if (adaptive()) {
    // Stream 0's count, then the pilot sums of each noise channel: stream 0's and both streams'.
    float* a_values = values + adaptive_base_;
    const bool pilot = index < static_cast<uint32_t>(settings_.pilot_spp / 2);
    a_values[0] = even ? 1.0f : 0.0f;
    for (size_t k = 0; k < noise_channels_.size(); ++k) {
      const float x_k = pilot ? values[noise_channels_[k]] : 0.0f;
      a_values[1 + 2 * k] = even ? x_k : 0.0f;
      a_values[2 + 2 * k] = x_k;
    }
  }
  film.add_sample(x, y, values);
}

void Renderer::feature_values(const FirstHit& first, const Vec3& camera_direction, float* f) const {
  for (int i = 0; i < kFeatureSlots; ++i) f[i] = 0.0f;
  if (!first.hit) {
    f[kSun] = 1.0f;
    f[kSky] = 1.0f;
    return;
  }
  for (int i = 0; i < 3; ++i) f[kNormalX + i] = first.shading_normal[i];
  f[kDepth] = first.t * glm::dot(camera_direction, forward_);
  f[kSun] = first.sun;
  f[kLeaf + static_cast<int>(first.feature_class) - 1] = 1.0f;  // kLeaf, kBark, kGround
}

BvhBuild bvh_build_for(const RenderSettings& settings) {
  return bvh_build_for(uint64_t(std::max(settings.width, 0)) * uint64_t(std::max(settings.height, 0)) *
                       uint64_t(std::max(settings.spp, 0)));
}

RenderStats Renderer::render(Film& film) {
  return render(film, film.window(), SampleRange{film.first_sample(), static_cast<uint32_t>(settings_.spp)});
}

Image Renderer::make_image(const Film& film) const {
  const size_t nc = channels_.size();
  std::vector<std::string> names;
  std::vector<PixelType> types;
  auto add = [&](std::string n, PixelType t) {
    names.push_back(std::move(n));
    types.push_back(t);
  };
  for (const auto& c : channels_.names) add(c, PixelType::Float);
  for (const auto& c : channels_.names) add("var." + c, PixelType::Float);
  for (const auto& c : channels_.names) add("albedo." + c, PixelType::Half);
  add("Z", PixelType::Float);
  add("N.X", PixelType::Half);
  add("N.Y", PixelType::Half);
  add("N.Z", PixelType::Half);
  add("P.X", PixelType::Float);
  add("P.Y", PixelType::Float);
  add("P.Z", PixelType::Float);
  add("id.instance", PixelType::UInt);
  add("id.object", PixelType::UInt);
  add("id.class", PixelType::UInt);
  add("id.variant", PixelType::UInt);
  if (settings_.material_ids) add("id.material", PixelType::UInt);
  // The samples each pixel took, where they vary (adaptive sampling, a progressive render).
  const bool spp_channel = adaptive() || progressive();
  if (spp_channel) add("spp", PixelType::UInt);
  const int first_feature = static_cast<int>(names.size());
  if (settings_.features) {
    for (const char* half : {"even.", "odd."})
      for (const auto& c : channels_.names) add(half + c, PixelType::Float);
    for (const auto& c : channels_.names) add("feature.albedo." + c, PixelType::Float);
    for (const char* f : kFeatureNames) add(std::string("feature.") + f, PixelType::Float);
    for (int i = 0; i < kFeaturesWithVariance; ++i)
      add(std::string("var.feature.") + kFeatureNames[i], PixelType::Float);
  }
  check_film(film);
  const PixelRegion& window = film.window();
  Image image = sylva::make_image(window.width(), window.height(), names);
  image.types = types;
  const int z = static_cast<int>(3 * nc);
  const int material = settings_.material_ids ? z + 11 : -1;
  const Vec3 forward = glm::normalize(scene_.camera.target - scene_.camera.position);

  tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(window.y0, window.y1, [&](int y) {
      const int iy = y - window.y0;
      for (int x = window.x0; x < window.x1; ++x) {
        const int ix = x - window.x0;
        for (size_t c = 0; c < nc; ++c) {
          image.at(ix, iy, static_cast<int>(c)) = static_cast<float>(channel_mean(film, x, y, static_cast<int>(c)));
          image.at(ix, iy, static_cast<int>(nc + c)) =
              static_cast<float>(channel_variance_of_mean(film, x, y, static_cast<int>(c)));
          image.at(ix, iy, static_cast<int>(2 * nc + c)) =
              static_cast<float>(film.mean(x, y, static_cast<int>(nc + c)));
        }
        // First-hit AOVs through the pixel centre (pinhole ray: labels are not blurred).
        const Ray ray = camera_.generate_ray(Vec2(x + 0.5f, y + 0.5f), Vec2(0.5f));
        RayHit hit;
        if (embree_.intersect(ray, &hit)) {
          const HitContext si = integrator_->interaction(ray, hit);
          const Vec3 n = glm::dot(si.ng, ray.direction) > 0 ? -si.ng : si.ng;
          image.at(ix, iy, z) = hit.t * glm::dot(ray.direction, forward);
          image.at(ix, iy, z + 1) = n.x;
          image.at(ix, iy, z + 2) = n.y;
          image.at(ix, iy, z + 3) = n.z;
          for (int i = 0; i < 3; ++i) image.at(ix, iy, z + 4 + i) = si.p[i];
          image.at(ix, iy, z + 7) = static_cast<float>(hit.instance + 1);
          const Instance& inst = scene_.instances[hit.instance];
          image.at(ix, iy, z + 8) = static_cast<float>(inst.object_id);
          image.at(ix, iy, z + 9) = static_cast<float>(inst.class_id);
          image.at(ix, iy, z + 10) = static_cast<float>(inst.variant_id);
          if (material >= 0) image.at(ix, iy, material) = static_cast<float>(si.material + 1);
        } else {
          image.at(ix, iy, z) = 1e10f;
          // The sky: a point 10¹⁰ m along the ray, like Z.
          for (int i = 0; i < 3; ++i) image.at(ix, iy, z + 4 + i) = ray.origin[i] + 1e10f * ray.direction[i];
        }
        if (spp_channel) image.at(ix, iy, first_feature - 1) = static_cast<float>(film.count(x, y));
        if (settings_.features) write_features(image, film, x, y, first_feature);
      }
    });
  });
  return image;
}

void Renderer::write_features(Image& image, const Film& film, int x, int y, int first_channel) const {
  const PixelRegion& window = film.window();
  const int ix = x - window.x0, iy = y - window.y0, nc = static_cast<int>(channels_.size());
  // A whole film starts at sample 0, so it has ⌈n/2⌉ even samples; adaptive: stream 0's.
  const uint64_t n = film.count(x, y), n_even = adaptive() ? stream0_count(film, x, y) : (n + 1) / 2;
  const uint64_t n_odd = n - n_even;
  int out = first_channel;
  for (int c = 0; c < nc; ++c) {
    const double sum = film.sum(x, y, c), even = film.sum(x, y, even_channel(static_cast<size_t>(c)));
    image.at(ix, iy, out + c) = n_even ? static_cast<float>(even / static_cast<double>(n_even)) : 0.0f;
    image.at(ix, iy, out + nc + c) = n_odd ? static_cast<float>((sum - even) / static_cast<double>(n_odd)) : 0.0f;
  }
  out += 2 * nc;
  const int features = 3 * nc;
  const double sky = film.mean(x, y, features + kSky);
  for (int c = 0; c < nc; ++c) image.at(ix, iy, out + c) = static_cast<float>(film.mean(x, y, nc + c) + sky);
  out += nc;
  for (int i = 0; i < kFeatureSlots; ++i) image.at(ix, iy, out + i) = static_cast<float>(film.mean(x, y, features + i));
  out += kFeatureSlots;
  for (int i = 0; i < kFeaturesWithVariance; ++i)
    image.at(ix, iy, out + i) = static_cast<float>(film.variance_of_mean(x, y, features + i));
}

}  // namespace sylva
