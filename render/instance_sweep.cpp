#include "render/instance_sweep.h"

#include "core/error.h"

#include <fmt/core.h>

#include <immintrin.h>  // AVX: the sweep's box test

#include <algorithm>
#include <limits>

namespace sylva {

InstanceBoxes::InstanceBoxes(const std::vector<Bounds3>& boxes) : boxes_(boxes) {
  if (boxes.size() > kMaxCopies)
    throw Error(fmt::format("{} copies are more than a sweep holds ({})", boxes.size(), kMaxCopies));
  avx_ = __builtin_cpu_supports("avx");
  // Every box widened by a micrometre plus a few ulps of its coordinates: a ray parallel to a flat
  // box (a ground plane) and in its plane, whose direction has a zero component (1/d taken as
  // 10¹⁸), then meets that slab over at least 10¹² m of its length rather than over none.
  const auto widen = [](Vec3 v, float sign) {
    return v + sign * (kBoxPadding_m + 4.0f * std::numeric_limits<float>::epsilon() * glm::abs(v));
  };
  for (Bounds3& b : boxes_)
    if (!b.empty()) b = Bounds3{widen(b.lo, -1.0f), widen(b.hi, 1.0f)};
  lanes_.assign(6 * ((boxes.size() + kLanes - 1) / kLanes), Lanes{});
  for (size_t j = 0; j < boxes_.size(); ++j) {
    const Bounds3& b = boxes_[j];
    if (b.empty()) continue;
    valid_ |= uint64_t{1} << j;
    Lanes* group = &lanes_[6 * (j / kLanes)];
    for (int a = 0; a < 3; ++a) {
      group[a].v[j % kLanes] = b.lo[a];
      group[3 + a].v[j % kLanes] = b.hi[a];
    }
  }
  overlapping_.assign(boxes_.size(), 0);
  for (size_t j = 0; j < boxes_.size(); ++j)
    for (size_t k = 0; k < boxes_.size(); ++k) {
      const Bounds3 &a = boxes_[j], &b = boxes_[k];
      if (k == j || a.empty() || b.empty()) continue;
      const Vec3 size = glm::max(glm::max(glm::abs(a.lo), glm::abs(a.hi)), glm::max(glm::abs(b.lo), glm::abs(b.hi)));
      const float margin = 1e-5f * std::max({size.x, size.y, size.z}) + 1e-6f;
      if (glm::all(glm::lessThanEqual(b.lo, a.hi + margin)) && glm::all(glm::lessThanEqual(a.lo, b.hi + margin)))
        overlapping_[j] |= uint64_t{1} << k;
    }
}

namespace {

// InstanceBoxes::meet's eight lanes at a time.
__attribute__((target("avx"))) uint64_t meet_avx(const float* lanes, size_t groups, const Vec3& o, const Vec3& inv,
                                                 float t_max, float* near) {
  const __m256 ox = _mm256_set1_ps(o.x), oy = _mm256_set1_ps(o.y), oz = _mm256_set1_ps(o.z);
  const __m256 ix = _mm256_set1_ps(inv.x), iy = _mm256_set1_ps(inv.y), iz = _mm256_set1_ps(inv.z);
  const __m256 zero = _mm256_setzero_ps(), far = _mm256_set1_ps(t_max);
  const __m256 down = _mm256_set1_ps(InstanceBoxes::kSlabDown), up = _mm256_set1_ps(InstanceBoxes::kSlabUp);
  uint64_t meets = 0;
  for (size_t g = 0; g < groups; ++g) {
    const float* b = lanes + 6 * InstanceBoxes::kLanes * g;
    const __m256 x0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(b), ox), ix);
    const __m256 y0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(b + 8), oy), iy);
    const __m256 z0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(b + 16), oz), iz);
    const __m256 x1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(b + 24), ox), ix);
    const __m256 y1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(b + 32), oy), iy);
    const __m256 z1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(b + 40), oz), iz);
    const __m256 t_in = _mm256_max_ps(_mm256_max_ps(_mm256_min_ps(x0, x1), _mm256_min_ps(y0, y1)),
                                      _mm256_max_ps(_mm256_min_ps(z0, z1), zero));
    const __m256 t_out = _mm256_min_ps(_mm256_min_ps(_mm256_max_ps(x0, x1), _mm256_max_ps(y0, y1)),
                                       _mm256_min_ps(_mm256_max_ps(z0, z1), far));
    const __m256 t_near = _mm256_mul_ps(t_in, down);
    _mm256_store_ps(near + InstanceBoxes::kLanes * g, t_near);
    const __m256 meet = _mm256_cmp_ps(t_near, _mm256_mul_ps(t_out, up), _CMP_LE_OQ);
    meets |= static_cast<uint64_t>(_mm256_movemask_ps(meet)) << (InstanceBoxes::kLanes * g);
  }
  return meets;
}

}  // namespace

uint64_t InstanceBoxes::meet(const Vec3& o, const Vec3& inv, float t_max, float* near) const {
  static_assert(sizeof(Lanes) == kLanes * sizeof(float));
  if (!avx_) return meet_portable(o, inv, t_max, near);
  return meet_avx(lanes_.empty() ? nullptr : lanes_[0].v, lanes_.size() / 6, o, inv, t_max, near) & valid_;
}

uint64_t InstanceBoxes::meet_portable(const Vec3& o, const Vec3& inv, float t_max, float* near) const {
  uint64_t meets = 0;
  for (uint64_t m = valid_; m != 0; m &= m - 1) {
    const auto j = static_cast<size_t>(std::countr_zero(m));
    near[j] = entry(j, o, inv, t_max);
    meets |= static_cast<uint64_t>(near[j] < std::numeric_limits<float>::infinity()) << j;
  }
  return meets;
}

}  // namespace sylva
