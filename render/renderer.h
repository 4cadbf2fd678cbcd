#pragma once
// Rendering a Scene into a Film, and a Film into an Image (EXR channels).
//
// Work is split into square tiles rendered in parallel with TBB; every sample's random numbers
// come from a PCG32 stream hashed from (seed, pixel, sample index), and each pixel's samples are
// accumulated in order by one thread, so the result is bit-identical at any thread count and
// whether or not the render was interrupted and resumed.

#include "core/band.h"
#include "core/image.h"
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
  int threads = 0;  // 0 = all hardware threads
  int tile_size = 16;
  std::vector<Band> bands;  // at least one
  IntegratorSettings integrator;
  bool fault_no_shadow_alpha = false;  // fault injection (golden power tests): see EmbreeScene
  bool progress = true;                // progress bar on stderr (only when stderr is a terminal)
  // Set asynchronously (e.g. by SIGINT) to stop early; every pixel keeps the samples it finished.
  const std::atomic<bool>* cancel = nullptr;
};

struct RenderStats {
  double seconds = 0;
  uint64_t samples = 0;  // path samples added in this call
  uint64_t rays = 0;
  bool interrupted = false;
  EmbreeStats embree;
};

class Renderer {
 public:
  // Builds the acceleration structures. `scene` must outlive the renderer.
  Renderer(const Scene& scene, RenderSettings settings);
  ~Renderer();

  // A film sized and laid out for these settings.
  Film make_film() const;
  // Adds samples to every pixel until it has settings.spp (or cancel is set).
  RenderStats render(Film& film);
  // Channels: each band's channels (mean radiance), "var.<C>" (variance of the mean), the albedo
  // AOV per band channel ("albedo.<C>"), and the first-hit AOVs from a ray through each pixel
  // centre: "Z" (camera-space depth in m; 1e10 for the sky), "N.X/N.Y/N.Z" (world geometric
  // normal facing the camera), "id.instance" (instance index + 1, 0 = sky) and "id.object".
  Image make_image(const Film& film) const;

  const EmbreeStats& embree_stats() const;
  const std::vector<std::string>& radiance_channels() const { return channels_; }

 private:
  void render_pixel(Film& film, int x, int y, uint32_t first_sample, uint32_t end_sample, uint64_t& rays) const;

  const Scene& scene_;
  RenderSettings settings_;
  std::unique_ptr<EmbreeScene> embree_;
  Environment environment_;
  std::unique_ptr<Integrator> integrator_;
  Camera camera_;
  WavelengthSampler wavelengths_;
  std::vector<std::string> channels_;          // radiance channel names, band after band
  std::vector<const DenseSpectrum*> weights_;  // w_c(λ) per radiance channel
  std::vector<float> weight_integrals_;        // ∫ w_c dλ, to normalise the albedo AOV
};

}  // namespace sylva
