#pragma once
// The world boxes of a scene's few placed copies, met by a ray all at once: the top level of the
// "sweep" (render/embree_scene.h), which traces a scene of at most kMaxCopies copies without
// Embree's instance BVH. One pass of slab tests, eight boxes per AVX register, finds every box the
// ray's segment meets and where it enters each; the caller then enters those copies' prototype BVHs
// nearest first. For a few dozen copies this is no more work than the descent through Embree's
// instance BVH, and it lets the caller leave copies out: the copy a ray leaves (traced first) and,
// when the ray ends inside that copy's box, every copy whose box does not overlap it
// (bench/README.md, "A sweep in place of the instance BVH").

#include "geometry/mesh.h"

#include <cstdint>
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
  bool contains(size_t j, const Vec3& p) const;

  // 1/d for the slab tests, a zero component taken as 10⁻¹⁸ of its sign: finite slab distances, no 0·∞.
  static Vec3 inverse_direction(const Vec3& d);

  // The boxes the segment o + t·d, 0 <= t <= t_max, meets (bit j: box j; inv = inverse_direction(d))
  // and a lower bound of where it enters each, near[j] (near holds size() floats, 32-byte aligned).
  // Conservative, as Embree's robust traversal: the slab distances (b − o)·(1/d) are widened by a
  // few ulps, so rounding never drops a box the segment grazes. AVX where the processor has it,
  // meet_portable elsewhere: the same bits.
  uint64_t meet(const Vec3& o, const Vec3& inv, float t_max, float* near) const;
  // The same a box at a time, without AVX (the operations of meet's lanes, one by one).
  uint64_t meet_portable(const Vec3& o, const Vec3& inv, float t_max, float* near) const;
  // Where the segment enters box j (as meet), or infinity when it misses.
  float entry(size_t j, const Vec3& o, const Vec3& inv, float t_max) const;

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
size_t take_nearest(uint64_t& left, const float* near);

}  // namespace sylva
