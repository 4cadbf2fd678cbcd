#pragma once
// The random numbers of one pixel sample (a camera path): independent PCG32 draws, or Owen-scrambled
// Sobol' points (core/sobol.h), the default.
//
// Every draw names its dimension: the event it belongs to (the camera, then each event along the
// path: a scattering, a crown boundary crossed) and its use there (SampleDim). A Sobol' sample
// reads that dimension of the pixel's sequence at the sample's index, so the same use at the same
// event draws from the same stratified sequence in every sample of the pixel (pixel position with
// pixel position, first light sample with first light sample), and no dimension is read twice in
// one path. The sequence of a dimension is a hash of (seed, pixel, event, use): a sample depends on
// nothing but those and its index, so renders are bit-identical at any thread count, resumed, or
// split by samples, tiles or ranks and merged. The independent sampler ignores the names and draws
// from one PCG32 stream in the order of the calls (the bits of every render before Sobol' sampling).

#include "core/hash.h"
#include "core/rng.h"
#include "core/sobol.h"

#include <cstdint>

namespace sylva {

enum class SamplerKind : uint8_t { kIndependent, kSobol };
inline const char* sampler_name(SamplerKind kind) { return kind == SamplerKind::kSobol ? "sobol" : "independent"; }

// The uses of random numbers within one event, each a dimension of its own (1-D or 2-D).
enum class SampleDim : uint32_t {
  // The camera event.
  kPixel,       // 2-D: position in the pixel
  kLens,        // 2-D: position on the lens
  kWavelength,  // 1-D: the wavelengths' CDF position
  kHero,        // 1-D: which carried wavelength is the hero (SampledWavelengths::hero)
  // A path event.
  kFreeFlight,     // 1-D: distance to a collision in a turbid crown
  kHaze,           // 1-D: distance to a collision in the haze
  kLight,          // 2-D: next-event estimation: a point of the sun or sky
  kLightSelect,    // 1-D: sun or sky
  kEmitterSelect,  // 1-D: which emitter triangle
  kEmitter,        // 2-D: a point on it
  kScatter,        // 2-D: the next direction (BSDF, phase function)
  kScatterNormal,  // 2-D: a crown leaf's normal (the turbid crowns' phase function)
  kLobe,           // 1-D: which lobe
  kRoulette,       // 1-D: Russian roulette
  kCount
};

class PathSampler {
 public:
  PathSampler() = default;
  // Independent draws from `rng`, which the caller owns and which advances with each draw.
  explicit PathSampler(Pcg32& rng) : rng_(&rng) {}
  // Sample `index` of pixel `pixel`. kIndependent: `rng` is reseeded from (seed, pixel, index) as
  // every render before Sobol' sampling did; kSobol: `rng` is not used.
  void start(SamplerKind kind, Pcg32& rng, uint64_t seed, uint64_t pixel, uint32_t index) {
    kind_ = kind;
    rng_ = &rng;
    if (kind == SamplerKind::kIndependent) {
      rng = Pcg32(hash_ids(seed, pixel, index));
    } else {
      pixel_seed_ = hash_ids(seed, pixel);
      index_ = index;
    }
    event_ = 0;
  }
  // Sample `index` of stream `stream` (0 or 1) of pixel `pixel`: adaptive sampling's two
  // independent sequences per pixel (render/renderer.h). Stream s's sample j is the pixel's sample
  // 2j + s for the independent sampler; for Sobol' each stream is its own scrambled sequence.
  void start_stream(SamplerKind kind, Pcg32& rng, uint64_t seed, uint64_t pixel, uint32_t stream, uint32_t index) {
    if (kind == SamplerKind::kIndependent) return start(kind, rng, seed, pixel, 2 * index + stream);
    start(kind, rng, seed, pixel, index);
    pixel_seed_ = hash_ids(pixel_seed_, uint64_t{0x5354524du} + stream);
  }
  // Moves to the dimensions of the path's event `event` (≥ 1; 0 is the camera's).
  void start_event(uint32_t event) { event_ = event; }

  float get1d(SampleDim dim) {
    if (kind_ == SamplerKind::kIndependent) return rng_->uniform();
    return sobol_1d(index_, dimension_seed(dim));
  }
  // Independent: drawn in uniform2's order.
  Vec2 get2d(SampleDim dim) {
    if (kind_ == SamplerKind::kIndependent) return uniform2(*rng_);
    return sobol_2d(index_, dimension_seed(dim));
  }
  // Draw j of n of one use at one event (several light samples at a vertex): Sobol' point
  // index·n + j of the dimension's sequence, so a sample's n points and those of all the pixel's
  // samples together stay stratified (n a power of two keeps them elementary intervals). j = 0 of
  // n = 1 is get1d(dim) / get2d(dim); the independent sampler draws as those do.
  float get1d(SampleDim dim, uint32_t j, uint32_t n) {
    if (kind_ == SamplerKind::kIndependent) return rng_->uniform();
    return sobol_1d(index_ * n + j, dimension_seed(dim));
  }
  Vec2 get2d(SampleDim dim, uint32_t j, uint32_t n) {
    if (kind_ == SamplerKind::kIndependent) return uniform2(*rng_);
    return sobol_2d(index_ * n + j, dimension_seed(dim));
  }

 private:
  uint32_t dimension_seed(SampleDim dim) const {
    return static_cast<uint32_t>(
        mix64(pixel_seed_ ^
              (static_cast<uint64_t>(event_) * static_cast<uint64_t>(SampleDim::kCount) + static_cast<uint64_t>(dim))));
  }

  SamplerKind kind_ = SamplerKind::kIndependent;
  Pcg32* rng_ = nullptr;
  uint64_t pixel_seed_ = 0;
  uint32_t index_ = 0;
  uint32_t event_ = 0;
};

}  // namespace sylva
