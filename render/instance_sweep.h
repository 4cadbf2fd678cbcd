#pragma once
// The world boxes of a scene's few placed copies, met by a ray all at once: the top level of the
// "sweep" (render/embree_scene.h), which traces a scene of at most kMaxCopies copies without
// Embree's instance BVH. One pass of slab tests, eight boxes per AVX register, finds every box the
// ray's segment meets and where it enters each; the caller then enters those copies' prototype BVHs
// nearest first. For a few dozen copies this is no more work than the descent through Embree's
// instance BVH, and it lets the caller leave copies out: the copy a ray leaves (traced first) and,
// when the ray ends inside that copy's box, every copy whose box does not overlap it
// (bench/README.md, "A sweep in place of the instance BVH").

#include "core/simd.h"
#include "geometry/mesh.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

namespace sylva {

class InstanceBoxes {
 public:
  static constexpr size_t kMaxCopies = 64;  // one bit each in a 64-bit mask
  static constexpr size_t kLanes = 8;       // boxes per AVX register
  // Each box is widened by this much plus 4 ulps of its coordinates (the constructor).
  static constexpr float kBoxPadding_m = 1e-6f;

  InstanceBoxes() = default;
  // Copy j's world box is boxes[j], widened (kBoxPadding_m); an empty box (an empty prototype, a
  // copy flattened to nothing) is never met. Throws sylva::Error beyond kMaxCopies.
  explicit InstanceBoxes(const std::vector<Bounds3>& boxes);

  size_t size() const { return boxes_.size(); }
  const Bounds3& box(size_t j) const { return boxes_[j]; }  // widened
  // Bit j: copy j has a box.
  uint64_t valid() const { return valid_; }
  // Bit k: box k overlaps box j (k ≠ j), within a margin far above the rounding of a point on a ray
  // (10⁻⁵ of the coordinates' magnitude plus a micrometre): a ray segment inside box j can meet no
  // copy's geometry but these.
  uint64_t overlapping(size_t j) const { return overlapping_[j]; }
  bool contains(size_t j, const Vec3& p) const {
    const Bounds3& b = boxes_[j];
    return p.x >= b.lo.x && p.y >= b.lo.y && p.z >= b.lo.z && p.x <= b.hi.x && p.y <= b.hi.y && p.z <= b.hi.z;
  }

  // 1/d for the slab tests, a zero component taken as 10⁻¹⁸ of its sign: finite slab distances, no 0·∞.
  static Vec3 inverse_direction(const Vec3& d) {
    const __m128 v = _mm_setr_ps(d.x, d.y, d.z, 1.0f);
    const __m128 sign_bit = _mm_set1_ps(-0.0f);
    const __m128 magnitude = _mm_max_ps(_mm_andnot_ps(sign_bit, v), _mm_set1_ps(1e-18f));
    return simd::store(_mm_div_ps(_mm_set1_ps(1.0f), _mm_or_ps(magnitude, _mm_and_ps(v, sign_bit))));
  }

  // The slab distances widened by a few ulps, as Embree's robust traversal does: the distance
  // (b − o)·(1/d) is a difference before the product, so its error is relative to the distance
  // itself however far the origin lies from the box, and these factors cover it.
  static constexpr float kSlabDown = 1.0f - 4.0f * std::numeric_limits<float>::epsilon();
  static constexpr float kSlabUp = 1.0f + 4.0f * std::numeric_limits<float>::epsilon();

  // The boxes the segment o + t·d, 0 <= t <= t_max, meets (bit j: box j; inv = inverse_direction(d))
  // and a lower bound of where it enters each, near[j]. `near` holds kMaxCopies floats, 32-byte
  // aligned: whole groups of kLanes are written. Conservative, as Embree's robust traversal: the
  // slab distances (b − o)·(1/d) are widened by a few ulps, so rounding never drops a box the
  // segment grazes. AVX where the processor has it, meet_portable elsewhere: the same bits.
  uint64_t meet(const Vec3& o, const Vec3& inv, float t_max, float* near) const;
  // The same a box at a time, without AVX (the operations of meet's lanes, one by one).
  uint64_t meet_portable(const Vec3& o, const Vec3& inv, float t_max, float* near) const;
  // Where the segment enters box j (as meet), or infinity when it misses: meet's operations for one
  // lane (a minimum or maximum of two equal values may differ in the sign of a zero, which no
  // decision reads).
  float entry(size_t j, const Vec3& o, const Vec3& inv, float t_max) const {
    const Bounds3& b = boxes_[j];
    float t_in = 0.0f, t_out = t_max;
    for (int a = 0; a < 3; ++a) {
      const float t0 = (b.lo[a] - o[a]) * inv[a], t1 = (b.hi[a] - o[a]) * inv[a];
      t_in = std::max(t_in, std::min(t0, t1));
      t_out = std::min(t_out, std::max(t0, t1));
    }
    const float near = t_in * kSlabDown;
    return near <= t_out * kSlabUp ? near : std::numeric_limits<float>::infinity();
  }

 private:
  struct alignas(32) Lanes {
    float v[kLanes];
  };
  std::vector<Bounds3> boxes_;
  std::vector<Lanes> lanes_;  // per group of kLanes boxes: lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
  std::vector<uint64_t> overlapping_;
  uint64_t valid_ = 0;
  bool avx_ = false;  // the processor has AVX
};

// Removes from `left` (non-zero) the box that begins nearest, near[j], and returns its index (the
// lowest of equals).
inline size_t take_nearest(uint64_t& left, const float* near) {
  auto best = static_cast<size_t>(std::countr_zero(left));
  for (uint64_t m = left & (left - 1); m != 0; m &= m - 1) {
    const auto j = static_cast<size_t>(std::countr_zero(m));
    if (near[j] < near[best]) best = j;
  }
  left &= ~(uint64_t{1} << best);
  return best;
}

}  // namespace sylva
