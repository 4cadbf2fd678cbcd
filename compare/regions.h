#pragma once
// Local tests of an image comparison (docs/compare.md, "Local tests"): mean-bias and variance tests
// over regions of the image, all in one family whose false-alarm rate Holm's step-down procedure
// holds at one α.
//
// Regions, each a set of pixels:
//   image        the whole image;
//   tile         square tiles of `tile` pixels (partial at the right and bottom edges);
//   grid         a coarse grid of `grid` × `grid` cells (only when its cells are at least twice a tile);
//   class        the pixels of one `id.class` value (> 0) of the reference;
//   object       the pixels of one `id.object` value (> 0);
//   sky          the pixels where `id.instance` is 0 (nothing hit);
//   material     the pixels of one `id.material` value (> 0): renders made with --material-ids.
// Label regions (class, object, sky, material) need the reference's id channels and at least `min_pixels`
// pixels; without ids they are simply absent.
//
// Per region and z-tested channel, over the pixels that enter the sums (finite, not rejected on
// their own; image_compare.h), with d = test − ref and σ² = Var(d) per pixel:
//   bias:      z = Σd / √Σσ²                two-sided p;  mean shift = Σd / Σ|ref|
//   variance:  ratio = mean(z_i²), t = (ratio − 1) / (s(z²)/√n)   one-sided p (too much scatter)
// The variance test is self-normalised (s(z²) the sample standard deviation of the z_i²), so a
// heavy-tailed radiance does not break it; it is run on regions of at least kMinVariancePixels.
// Holm (1979): sort the family's m p-values; the k-th smallest (k from 0) rejects while every
// smaller one rejected and p ≤ α/(m − k). Valid under any dependence between the tests (the regions
// overlap), and every region it lists as failing is a finding at family-wise level α.

#include "core/image.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace sylva {

enum class RegionKind : uint8_t { Image, Tile, Grid, Class, Object, Sky, Material };

// "image", "tile", "grid", "class", "object", "sky", "material"
const char* region_kind_name(RegionKind kind);

inline constexpr int64_t kMinVariancePixels = 32;

struct RegionTest {
  std::string channel;
  RegionKind kind = RegionKind::Image;
  int64_t label = 0;   // class, object or material id; tile or grid cell index; 0 for image and sky
  int x0 = 0, y0 = 0;  // bounding box of the region's pixels: [x0, x1) × [y0, y1)
  int x1 = 0, y1 = 0;
  int64_t pixels = 0;  // pixels in the region
  int64_t tested = 0;  // ... that entered the sums
  double bias_z = 0.0, bias_p = 1.0;
  double mean_shift = 0.0;      // Σd / Σ|ref| (+0.05 for a region 5 % too bright)
  double variance_ratio = 1.0;  // mean z²: observed scatter / predicted
  double variance_z = 0.0, variance_p = 1.0;
  bool variance_tested = false;                     // enough pixels for the variance test
  double bias_p_holm = 1.0, variance_p_holm = 1.0;  // Holm-adjusted p-values (failed iff ≤ α)
  bool bias_failed = false, variance_failed = false;
  bool failed() const { return bias_failed || variance_failed; }
};

// "image", "sky", "class 3", "object 12", "material 4", "tile (32,16)", "grid (64,0)".
std::string region_name(const RegionTest& region);

struct RegionOptions {
  int tile = 16;            // tile size; 0: no tiles
  int grid = 4;             // coarse grid cells per side; 0: none
  int64_t min_pixels = 64;  // smallest class, object or sky region tested
  bool labels = true;       // class, object, sky and material regions (when the reference has ids)
  bool variance = true;     // the variance test beside the bias test
};

// Which region of each partition every pixel belongs to (−1: none) and the regions' boxes.
struct RegionMaps {
  struct Partition {
    RegionKind kind = RegionKind::Image;
    std::vector<int32_t> of_pixel;          // region index per pixel, −1 outside every region
    std::vector<int64_t> labels;            // per region
    std::vector<int64_t> pixels;            // per region
    std::vector<std::array<int, 4>> boxes;  // per region: x0, y0, x1, y1
  };
  int width = 0, height = 0;
  int tile = 0, grid_cell = 0;  // sizes used (0: partition absent)
  std::vector<Partition> partitions;
};

RegionMaps make_region_maps(const Image& ref, const RegionOptions& options);

// Sums of one channel per region; add every pixel that enters the sums, then finish.
class RegionSums {
 public:
  explicit RegionSums(const RegionMaps& maps);
  void add(size_t pixel, double d, double variance, double ref);
  // The tests of this channel's regions (unadjusted; holm() decides).
  std::vector<RegionTest> finish(const std::string& channel, bool variance) const;

 private:
  struct Sum {
    int64_t n = 0;
    double d = 0.0, var = 0.0, abs_ref = 0.0, z2 = 0.0, z4 = 0.0;
  };
  const RegionMaps* maps_;
  std::vector<std::vector<Sum>> sums_;  // per partition, per region
};

// Holm's step-down over every bias and variance p-value of `tests` at level alpha: sets the
// adjusted p-values and the failed flags. Returns the family size m.
int64_t holm(std::vector<RegionTest>& tests, double alpha);

}  // namespace sylva
