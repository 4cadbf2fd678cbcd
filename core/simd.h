#pragma once
// GLM's vector arithmetic on one SSE register per vector, for the few hot paths where GLM's scalar
// code is the cost (Integrator::interaction; bench/README.md, "Four at a time"). Each
// function performs GLM's operations in GLM's order, one per lane, so it gives GLM's bits exactly
// (tests/core/test_simd.cpp checks that on random inputs): a change of renderer code to these
// helpers moves no pixel.

#include "core/math.h"

#include <emmintrin.h>  // SSE2 only: the x86-64 baseline (docs/design.md §10, "Build cost")

namespace sylva::simd {

// (x, y, z, 0). No load past the Vec3: an array's last element may end a page.
inline __m128 load(const Vec3& v) { return _mm_setr_ps(v.x, v.y, v.z, 0.0f); }
inline Vec3 store(__m128 v) {
  alignas(16) float f[4];
  _mm_store_ps(f, v);
  return {f[0], f[1], f[2]};
}
inline __m128 splat(float s) { return _mm_set1_ps(s); }
// Per lane mask ? a : b (mask all ones or all zeros per lane, as the comparisons give).
inline __m128 select(__m128 mask, __m128 a, __m128 b) { return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b)); }

// glm::cross: (a.y·b.z − b.y·a.z, a.z·b.x − b.z·a.x, a.x·b.y − b.x·a.y).
inline __m128 cross(__m128 a, __m128 b) {
  const __m128 a_yzx = _mm_shuffle_ps(a, a, _MM_SHUFFLE(3, 0, 2, 1));
  const __m128 b_yzx = _mm_shuffle_ps(b, b, _MM_SHUFFLE(3, 0, 2, 1));
  const __m128 a_zxy = _mm_shuffle_ps(a, a, _MM_SHUFFLE(3, 1, 0, 2));
  const __m128 b_zxy = _mm_shuffle_ps(b, b, _MM_SHUFFLE(3, 1, 0, 2));
  return _mm_sub_ps(_mm_mul_ps(a_yzx, b_zxy), _mm_mul_ps(b_yzx, a_zxy));
}

// glm::dot of two Vec3: (a.x·b.x + a.y·b.y) + a.z·b.z.
inline float dot(__m128 a, __m128 b) {
  const __m128 p = _mm_mul_ps(a, b);
  const __m128 xy = _mm_add_ss(p, _mm_shuffle_ps(p, p, _MM_SHUFFLE(1, 1, 1, 1)));
  return _mm_cvtss_f32(_mm_add_ss(xy, _mm_shuffle_ps(p, p, _MM_SHUFFLE(2, 2, 2, 2))));
}

// A Mat3 (or a Mat4's linear part) as its three columns.
struct Columns3 {
  __m128 c0, c1, c2;
};
inline Columns3 linear_part(const Mat4& m) { return {load(Vec3(m[0])), load(Vec3(m[1])), load(Vec3(m[2]))}; }

// glm's Mat3 · Vec3: per row, m[0][i]·v.x + m[1][i]·v.y + m[2][i]·v.z, left to right.
inline __m128 transform(const Columns3& m, __m128 v) {
  const __m128 x = _mm_shuffle_ps(v, v, _MM_SHUFFLE(0, 0, 0, 0));
  const __m128 y = _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 1, 1, 1));
  const __m128 z = _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 2, 2, 2));
  return _mm_add_ps(_mm_add_ps(_mm_mul_ps(m.c0, x), _mm_mul_ps(m.c1, y)), _mm_mul_ps(m.c2, z));
}

// Vec3(m · Vec4(p, 1)) as glm's Mat4 · Vec4 computes it: (m[0]·x + m[1]·y) + (m[2]·z + m[3]·1).
inline __m128 transform_point(const Mat4& m, __m128 p) {
  const __m128 x = _mm_shuffle_ps(p, p, _MM_SHUFFLE(0, 0, 0, 0));
  const __m128 y = _mm_shuffle_ps(p, p, _MM_SHUFFLE(1, 1, 1, 1));
  const __m128 z = _mm_shuffle_ps(p, p, _MM_SHUFFLE(2, 2, 2, 2));
  const __m128 c0 = _mm_loadu_ps(&m[0][0]), c1 = _mm_loadu_ps(&m[1][0]);
  const __m128 c2 = _mm_loadu_ps(&m[2][0]), c3 = _mm_loadu_ps(&m[3][0]);
  return _mm_add_ps(_mm_add_ps(_mm_mul_ps(c0, x), _mm_mul_ps(c1, y)), _mm_add_ps(_mm_mul_ps(c2, z), c3));
}

}  // namespace sylva::simd
