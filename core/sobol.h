#pragma once
// Owen-scrambled Sobol' points, shuffled and padded: Burley, "Practical Hash-based Owen
// Scrambling", JCGT 9(4), 2020, §3–5.
//
// A 2-D point is the first two Sobol' dimensions (a (0,2)-sequence in base 2) at a shuffled index,
// each coordinate Owen-scrambled by a hash; a 1-D point is the first dimension alone. Every
// further dimension of a path is padded: it draws from its own independently shuffled and scrambled
// copy of the same points (the seed differs), so no table of direction numbers is needed and a path
// may use any number of dimensions.
//
// The shuffle is itself an Owen scramble of the index read as a base-2 fraction with its bits
// reversed: it maps each aligned block [k·2^m, (k+1)·2^m) of indices onto another aligned block,
// so the first 2^m samples of a pixel are a whole aligned block of the sequence and keep its
// stratification: a (0,m,2)-net in 2-D, one point per interval of length 2^−m in 1-D
// (tests/core/test_sobol.cpp checks both exactly). The points are progressive: sample i is the same
// whatever the sample count, so a render can be extended, resumed or split and merged by sample
// index and give the same bits.

#include "core/math.h"

#include <cstdint>

namespace sylva {

inline uint32_t reverse_bits32(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

// A hash in which each bit depends only on the bits below it (and the seed): Laine & Karras's
// permutation with the constants of Burley 2020, listing 5.
inline uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// Owen's nested uniform scramble of x read as a base-2 fraction (most significant bit first): each
// bit is flipped or not by a hash of the bits above it (Burley 2020, listing 6).
inline uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
  return reverse_bits32(laine_karras_permutation(reverse_bits32(x), seed));
}

// The second Sobol' dimension: the generator matrix is Pascal's triangle mod 2 (primitive
// polynomial x + 1), column j being v_j = v_{j−1} xor (v_{j−1} >> 1), v_0 = 2^31. The first
// dimension is the van der Corput sequence, reverse_bits32(index).
inline uint32_t sobol_dimension1(uint32_t index) {
  uint32_t x = 0;
  uint32_t v = 0x80000000u;
  for (; index != 0; index >>= 1, v ^= v >> 1)
    if (index & 1u) x ^= v;
  return x;
}

// A 32-bit fixed-point fraction as a float in [0, 1): its top 24 bits, exact and never 1.
inline float fraction_to_float(uint32_t x) { return static_cast<float>(x >> 8) * 0x1p-24f; }

inline uint32_t sobol_seed_hash(uint32_t seed, uint32_t salt) {
  // A 32-bit mix (Chris Wellons's lowbias32) of the seed and a salt per use.
  uint32_t x = seed ^ (salt * 0x9e3779b9u);
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// Sample `index` of the 1-D sequence scrambled and shuffled by `seed`.
inline float sobol_1d(uint32_t index, uint32_t seed) {
  const uint32_t i = nested_uniform_scramble(index, seed);
  return fraction_to_float(nested_uniform_scramble(reverse_bits32(i), sobol_seed_hash(seed, 1)));
}

// Sample `index` of the 2-D sequence scrambled and shuffled by `seed`.
inline Vec2 sobol_2d(uint32_t index, uint32_t seed) {
  const uint32_t i = nested_uniform_scramble(index, seed);
  return {fraction_to_float(nested_uniform_scramble(reverse_bits32(i), sobol_seed_hash(seed, 1))),
          fraction_to_float(nested_uniform_scramble(sobol_dimension1(i), sobol_seed_hash(seed, 2)))};
}

}  // namespace sylva
