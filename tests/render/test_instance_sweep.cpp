// The sweep (render/instance_sweep.h): its box tests against a double-precision reference, its AVX
// lanes against the portable path, its overlaps; when EmbreeScene uses it; and the `from` hint of
// EmbreeScene::intersect and occluded, which must change no hit.

#include "render_test_scenes.h"

#include "core/error.h"
#include "core/rng.h"
#include "render/instance_sweep.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

namespace sylva::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

Vec3 random_direction(Pcg32& rng) {
  const float z = rng.uniform(-1.0f, 1.0f), phi = rng.uniform(0.0f, 6.2831853f);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Random boxes from centimetres to kilometres, some flat (a ground plane), some far from the origin.
std::vector<Bounds3> random_boxes(Pcg32& rng, size_t n) {
  std::vector<Bounds3> boxes;
  for (size_t j = 0; j < n; ++j) {
    const float scale = std::pow(10.0f, rng.uniform(-2.0f, 3.0f));
    const Vec3 centre = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)) * 20.0f * scale;
    Vec3 half = Vec3(rng.uniform(0.1f, 1), rng.uniform(0.1f, 1), rng.uniform(0.1f, 1)) * scale;
    if (j % 7 == 3) half.z = 0.0f;  // flat
    boxes.push_back(Bounds3{centre - half, centre + half});
  }
  return boxes;
}

// Where the segment o + t·d, 0 <= t <= t_max, enters and leaves box b, in double precision (the
// slabs of a zero direction component: all or nothing).
struct Span {
  double in, out;
};
Span exact_span(const Bounds3& b, const Vec3& o, const Vec3& d, float t_max) {
  double in = 0, out = t_max;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0f) {
      if (o[a] < b.lo[a] || o[a] > b.hi[a]) return {1, 0};
      continue;
    }
    const double t0 = (static_cast<double>(b.lo[a]) - o[a]) / d[a], t1 = (static_cast<double>(b.hi[a]) - o[a]) / d[a];
    in = std::max(in, std::min(t0, t1));
    out = std::min(out, std::max(t0, t1));
  }
  return {in, out};
}

// Every box the segment truly meets is met, no later than it truly begins; a box met that the
// segment misses is missed by a sliver of rounding only.
TEST(InstanceBoxes, MeetsWhatADoublePrecisionSlabTestMeets) {
  Pcg32 rng(17);
  int met = 0, grazing = 0;
  for (int scene = 0; scene < 40; ++scene) {
    std::vector<Bounds3> boxes = random_boxes(rng, 2 + scene % (InstanceBoxes::kMaxCopies - 1));
    boxes[0] = Bounds3{};  // an empty box: never met
    const InstanceBoxes sweep(boxes);
    EXPECT_EQ(sweep.valid() & 1, 0u);
    alignas(32) float near[InstanceBoxes::kMaxCopies];
    for (int r = 0; r < 1000; ++r) {
      // Origins near a box (inside, just outside, far away), most rays towards a point of a box,
      // some along an axis.
      const Bounds3& from = boxes[1 + rng.next_u32() % (boxes.size() - 1)];
      const Bounds3& to = boxes[1 + rng.next_u32() % (boxes.size() - 1)];
      const auto point = [&](const Bounds3& b, float lo, float hi) {
        return glm::mix(b.lo, b.hi, Vec3(rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi)));
      };
      const Vec3 o = point(from, -2.0f, 3.0f);
      Vec3 d = r % 4 == 0 ? random_direction(rng) : point(to, 0.0f, 1.0f) - o;
      if (r % 5 == 0) d[static_cast<int>(rng.next_u32() % 3)] = 0.0f;
      if (d == Vec3(0.0f)) continue;
      d = glm::normalize(d);
      const float t_max = r % 3 == 0 ? kInf : rng.uniform(0.0f, 1000.0f);
      const uint64_t meets = sweep.meet(o, InstanceBoxes::inverse_direction(d), t_max, near);
      for (size_t j = 0; j < boxes.size(); ++j) {
        if (boxes[j].empty()) {
          EXPECT_FALSE(meets >> j & 1);
          continue;
        }
        // Against the box itself: never dropped, entered no later. Against the box widened by
        // twice its padding plus 10⁻⁵ of its size: nothing beyond that is met.
        const Span span = exact_span(boxes[j], o, d, t_max);
        const Vec3 slack = Vec3(2.0f * InstanceBoxes::kBoxPadding_m) + 1e-5f * (boxes[j].hi - boxes[j].lo) +
                           4e-7f * glm::max(glm::abs(boxes[j].lo), glm::abs(boxes[j].hi));
        const Span wide = exact_span(Bounds3{boxes[j].lo - slack, boxes[j].hi + slack}, o, d, t_max);
        if (span.in <= span.out) {
          ++met;
          EXPECT_TRUE(meets >> j & 1) << "scene " << scene << " ray " << r << " box " << j;
          if (meets >> j & 1) {
            EXPECT_LE(near[j], span.in) << "scene " << scene << " ray " << r << " box " << j;
          }
        } else if (meets >> j & 1) {
          ++grazing;
          EXPECT_LE(wide.in, wide.out * (1 + 1e-6)) << "scene " << scene << " ray " << r << " box " << j;
        }
      }
    }
  }
  std::printf("[instance boxes] %d meetings, %d grazing boxes met within rounding\n", met, grazing);
  EXPECT_GT(met, 10000);
}

// A segment along a box's face, or ending on it, meets the box (the test is conservative).
TEST(InstanceBoxes, GrazingSegmentsMeetTheBox) {
  const InstanceBoxes sweep({Bounds3{Vec3(-1, -1, 0), Vec3(1, 1, 0)}, Bounds3{Vec3(2, 2, 2), Vec3(3, 3, 3)}});
  alignas(32) float near[InstanceBoxes::kMaxCopies];
  const auto meets = [&](Vec3 o, Vec3 d, float t_max) {
    return sweep.meet(o, InstanceBoxes::inverse_direction(d), t_max, near);
  };
  EXPECT_EQ(meets(Vec3(-5, 0, 0), Vec3(1, 0, 0), kInf) & 1, 1u);          // in the flat box's plane
  EXPECT_EQ(meets(Vec3(0, 0, 5), Vec3(0, 0, -1), 5.0f) & 1, 1u);          // ends on it
  EXPECT_EQ(meets(Vec3(0, 0, 5), Vec3(0, 0, -1), 4.99f) & 1, 0u);         // ends short of it
  EXPECT_EQ(meets(Vec3(3, 2.5f, 0), Vec3(0, 0, 1), kInf) & 2, 2u);        // along the cube's face x = 3
  EXPECT_EQ(meets(Vec3(3.01f, 2.5f, 0), Vec3(0, 0, 1), kInf) & 2, 0u);    // a centimetre beside it
  EXPECT_EQ(meets(Vec3(0, 0, 1e-5f), Vec3(1, 0, 0), kInf) & 1, 0u);       // parallel, 10 µm above it
  EXPECT_EQ(meets(Vec3(2.5f, 2.5f, 2.5f), Vec3(0, 1, 0), 0.0f) & 2, 2u);  // starts inside
}

// The AVX lanes and the portable path give the same boxes and the same entry distances, bit for bit.
TEST(InstanceBoxes, PortablePathGivesTheSameBits) {
  Pcg32 rng(5);
  int compared = 0;
  for (int scene = 0; scene < 20; ++scene) {
    const InstanceBoxes sweep(random_boxes(rng, InstanceBoxes::kMaxCopies - static_cast<size_t>(scene)));
    alignas(32) float a[InstanceBoxes::kMaxCopies], b[InstanceBoxes::kMaxCopies];
    for (int r = 0; r < 2000; ++r) {
      const Vec3 o = sweep.box(rng.next_u32() % sweep.size()).lo + 3.0f * random_direction(rng);
      const Bounds3& to = sweep.box(rng.next_u32() % sweep.size());
      const Vec3 aim = glm::mix(to.lo, to.hi, Vec3(rng.uniform(), rng.uniform(), rng.uniform())) - o;
      const Vec3 inv = InstanceBoxes::inverse_direction(r % 3 == 0 ? random_direction(rng) : glm::normalize(aim));
      const float t_max = r % 2 ? kInf : rng.uniform(0.0f, 100.0f);
      const uint64_t ma = sweep.meet(o, inv, t_max, a), mb = sweep.meet_portable(o, inv, t_max, b);
      ASSERT_EQ(ma, mb) << "scene " << scene << " ray " << r;
      for (uint64_t m = ma; m != 0; m &= m - 1) {
        const int j = std::countr_zero(m);
        ASSERT_EQ(std::bit_cast<uint32_t>(a[j]), std::bit_cast<uint32_t>(b[j])) << "scene " << scene << " box " << j;
        ASSERT_EQ(std::bit_cast<uint32_t>(a[j]),
                  std::bit_cast<uint32_t>(sweep.entry(static_cast<size_t>(j), o, inv, t_max)));
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 10000);
}

TEST(InstanceBoxes, InverseDirectionKeepsSignsAndAvoidsInfinity) {
  const Vec3 inv = InstanceBoxes::inverse_direction(Vec3(0.0f, -0.0f, -0.5f));
  EXPECT_EQ(inv.x, 1e18f);
  EXPECT_EQ(inv.y, -1e18f);
  EXPECT_EQ(inv.z, -2.0f);
}

TEST(InstanceBoxes, OverlapsAreSymmetricAndCountTouchingBoxes) {
  const InstanceBoxes sweep({Bounds3{Vec3(0), Vec3(1)},                      // 0
                             Bounds3{Vec3(1, 0, 0), Vec3(2, 1, 1)},          // 1: shares a face with 0
                             Bounds3{Vec3(2.001f, 0, 0), Vec3(3, 1, 1)},     // 2: a millimetre from 1
                             Bounds3{Vec3(-10, -10, -1), Vec3(10, 10, -1)},  // 3: flat, below all
                             Bounds3{Vec3(0.5f), Vec3(0.6f)},                // 4: inside 0
                             Bounds3{}});                                    // 5: empty
  EXPECT_EQ(sweep.overlapping(0), 0b10010u);
  EXPECT_EQ(sweep.overlapping(1), 0b00001u);
  EXPECT_EQ(sweep.overlapping(2), 0u);
  EXPECT_EQ(sweep.overlapping(3), 0u);
  EXPECT_EQ(sweep.overlapping(4), 0b00001u);
  EXPECT_EQ(sweep.overlapping(5), 0u);
  EXPECT_EQ(sweep.valid(), 0b011111u);
  EXPECT_TRUE(sweep.contains(0, Vec3(1.0f)));
  EXPECT_TRUE(sweep.contains(0, Vec3(1.0f, 1.0f, 1.0f + 0.5f * InstanceBoxes::kBoxPadding_m)));
  EXPECT_FALSE(sweep.contains(0, Vec3(1.0f, 1.0f, 1.0001f)));
}

TEST(InstanceBoxes, TakeNearestInOrderOfEntry) {
  const float near[5] = {3.0f, 1.0f, 2.0f, 1.0f, 0.5f};
  uint64_t left = 0b01111;  // box 4 is not among them
  std::vector<size_t> order;
  while (left != 0) order.push_back(take_nearest(left, near));
  EXPECT_EQ(order, (std::vector<size_t>{1, 3, 2, 0}));  // equals: the lower index first
}

TEST(InstanceBoxes, RefusesMoreCopiesThanItsMask) {
  EXPECT_THROW(InstanceBoxes(std::vector<Bounds3>(InstanceBoxes::kMaxCopies + 1)), Error);
}

TEST(InstanceSweep, AutomaticUpToItsLimit) {
  Scene s;
  s.prototypes.resize(1);
  s.instances.resize(InstanceBoxes::kMaxCopies);
  EXPECT_TRUE(uses_instance_sweep(s));
  s.instances.resize(InstanceBoxes::kMaxCopies + 1);
  EXPECT_FALSE(uses_instance_sweep(s));
  EXPECT_FALSE(uses_instance_array(s));
  // A cyclic plot counts its nine copies of every instance.
  s.instances.resize(8);
  s.plot = PlotDesc{true, Vec2(-1.0f), Vec2(1.0f), true};
  EXPECT_FALSE(uses_instance_sweep(s));
  s.instances.resize(7);
  EXPECT_TRUE(uses_instance_sweep(s));
  // Asked for: never with native instances or the array; refused beyond the limit, with the count.
  s.instance_level = InstanceLevel::native;
  EXPECT_FALSE(uses_instance_sweep(s));
  s.instance_level = InstanceLevel::array;
  EXPECT_FALSE(uses_instance_sweep(s));
  s.instance_level = InstanceLevel::sweep;
  EXPECT_TRUE(uses_instance_sweep(s));
  s.instances.resize(8);
  try {
    uses_instance_sweep(s);
    FAIL() << "a sweep of 72 copies was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("at most 64 copies, not 72"), std::string::npos) << e.what();
  }
}

// Rays leaving the surfaces they hit, as a path tracer's: with the surface's instance as `from` or
// without, the same hit bit for bit, and the same occlusion. The instance is also given wrongly (any
// `from` must give the same answer) and for rays that leave a ground plane.
void expect_hints_change_nothing(const Scene& scene, const char* what) {
  const EmbreeScene embree(scene);
  ASSERT_TRUE(embree.stats().instance_sweep) << what;
  Pcg32 rng(23);
  int bounces = 0, same_crown = 0;
  for (int r = 0; r < 4000; ++r) {
    // A first ray from above the stand, down into it.
    Ray ray{Vec3(rng.uniform(-5, 5), rng.uniform(-2, 7), 6.0f),
            glm::normalize(Vec3(rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f), -1.0f))};
    RayHit hit;
    if (!embree.intersect(ray, &hit)) continue;
    for (int bounce = 0; bounce < 4; ++bounce) {
      const Vec3 p = ray.origin + hit.t * ray.direction;
      const Vec3 d = random_direction(rng);
      // Off the surface along the new direction: a few millimetres (the integrator's offset is smaller;
      // here the hint's correctness, not the surface, is the question).
      const Ray next{p + 1e-3f * d, d};
      const uint32_t from = hit.instance;
      const uint32_t wrong = rng.next_u32() % static_cast<uint32_t>(scene.instances.size());
      RayHit plain, hinted, misled;
      const bool found = embree.intersect(next, &plain);
      EXPECT_EQ(embree.intersect(next, &hinted, from), found) << what << " ray " << r;
      EXPECT_EQ(embree.intersect(next, &misled, wrong), found) << what << " ray " << r;
      for (const RayHit* h : {&hinted, &misled}) {
        if (!found) break;
        EXPECT_EQ(std::bit_cast<uint32_t>(h->t), std::bit_cast<uint32_t>(plain.t)) << what << " ray " << r;
        EXPECT_EQ(h->instance, plain.instance) << what << " ray " << r;
        EXPECT_EQ(h->primitive, plain.primitive) << what << " ray " << r;
        EXPECT_EQ(h->kind, plain.kind) << what << " ray " << r;
        EXPECT_EQ(std::bit_cast<uint32_t>(h->u), std::bit_cast<uint32_t>(plain.u)) << what << " ray " << r;
      }
      const bool blocked = embree.occluded(next.origin, d, kInf);
      EXPECT_EQ(embree.occluded(next.origin, d, kInf, from), blocked) << what << " ray " << r;
      EXPECT_EQ(embree.occluded(next.origin, d, kInf, wrong), blocked) << what << " ray " << r;
      ++bounces;
      if (!found) break;
      same_crown += plain.instance == from;
      ray = next;
      hit = plain;
    }
  }
  std::printf("[instance sweep] %s: %d bounces, %d ending in the instance they left\n", what, bounces, same_crown);
  EXPECT_GT(bounces, 4000) << what;
  EXPECT_GT(same_crown, bounces / 10) << what;  // the shortcut is exercised
}

TEST(InstanceSweep, FromHintChangesNoHit) { expect_hints_change_nothing(stand_scene(), "stand"); }

// In a cyclic plot the ray is traced cell by cell from wrapped origins: the hint is not used there,
// and the sweep covers the nine copies of each instance.
TEST(InstanceSweep, CyclicPlotHasTheSameHitsAsNativeInstances) {
  Scene s = stand_scene();
  s.instances.resize(7);  // the ground and six copies: 63 with their shifted copies
  s.instances.erase(s.instances.begin());
  s.plot = PlotDesc{true, Vec2(-5.0f, -2.0f), Vec2(5.0f, 7.0f), true};
  Prototype floor;
  floor.triangles = make_plane(10, 9);
  s.instances.push_back({s.add_prototype(std::move(floor)), glm::translate(Mat4(1.0f), Vec3(0, 2.5f, 0)), 0});
  const EmbreeScene sweep(with_level(s, InstanceLevel::sweep)), native(with_level(s, InstanceLevel::native));
  ASSERT_TRUE(sweep.stats().instance_sweep);
  Pcg32 rng(9);
  int agree = 0, hits = 0;
  constexpr int kRays = 20000;
  for (int r = 0; r < kRays; ++r) {
    const Ray ray{Vec3(rng.uniform(-5, 5), rng.uniform(-2, 7), rng.uniform(0.1f, 4.0f)), random_direction(rng)};
    RayHit a, b;
    const bool fa = sweep.intersect(ray, &a, rng.next_u32() % 7), fb = native.intersect(ray, &b);
    hits += fb;
    agree += fa == fb && (!fa || (a.instance == b.instance && a.primitive == b.primitive &&
                                  std::abs(a.t - b.t) <= 1e-4f * (1.0f + b.t)));
  }
  std::printf("[instance sweep] cyclic plot: %d of %d rays agree with native instances (%d hits)\n", agree, kRays,
              hits);
  EXPECT_GT(hits, kRays / 2);
  EXPECT_GE(agree, kRays - kRays / 1000);  // grazing edges only
}

}  // namespace
}  // namespace sylva::test
