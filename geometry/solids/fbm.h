#pragma once
// Three-dimensional fractional Brownian motion (Fournier & Grindal §3–4: "three-dimensional
// fractional Brownian motion [MaVN68, FoFC82]" as the texture solid). A sum of octaves of lattice
// value noise: fbm(p) = Σ_{k<K} g^k v(λ^k p / s) / Σ_{k<K} g^k with g = λ^(−H), so the amplitude
// of each octave falls as (wavelength)^H: the Hurst exponent H sets the roughness (the structure
// function E[(F(x+δ)−F(x))²] grows as δ^(2H) between the finest and the coarsest wavelength, and a
// transect's power spectrum falls as f^−(1+2H)). Evaluated procedurally, so the texture has no
// tiling and is the same from every viewpoint and in every frame (it is a function of position in
// the crown's own coordinates only).

#include "core/math.h"

#include <cstdint>

namespace sylva {

struct FbmParams {
  float hurst = 0.5f;         // H in (0, 1]
  float lacunarity = 2.0f;    // λ > 1: frequency ratio of successive octaves
  int octaves = 5;            // K ≥ 1
  float wavelength_m = 1.0f;  // s: wavelength of the coarsest octave
  uint64_t seed = 1;
};

// Lattice value noise in [−1, 1]: random values at integer points, blended with the smoothstep
// 3t² − 2t³ along each axis. C¹, and |∂v/∂x_i| ≤ 3 (see fbm_lipschitz).
float value_noise(const Vec3& p, uint64_t seed);

// fBm in [−1, 1] (normalised by the sum of the octave amplitudes).
float fbm(const FbmParams& params, const Vec3& p);

// A proven Lipschitz constant of fbm(): |fbm(p) − fbm(q)| ≤ L |p − q|. Proof in fbm.cpp.
float fbm_lipschitz(const FbmParams& params);

}  // namespace sylva
