#pragma once
// Detection annotations of a rendered frame (docs/studies.md, "Annotations"): per target, the
// modal mask (the pixels whose `id.object` is the target), the amodal mask (the pixels the target
// covers with nothing else in the scene: the same pixel-centre rays against the target alone),
// their boxes, visible fraction and critical dimension; written as COCO, YOLO and Pascal VOC.

#include "core/image.h"
#include "scenes/scene_file.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sylva {

// An inclusive pixel box, x right and y down from the top-left pixel; empty when x1 < x0.
struct PixelBox {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  bool empty() const { return x1 < x0; }
  int width() const { return empty() ? 0 : x1 - x0 + 1; }
  int height() const { return empty() ? 0 : y1 - y0 + 1; }
};

struct TargetAnnotation {
  size_t target = 0;  // index in SceneFile::targets
  std::string name, label;
  uint32_t object_id = 0, class_id = 0;
  std::vector<uint8_t> modal;  // width × height, row-major, 1 where id.object is the target
  // Both boxes and masks are clipped to the image: the amodal box bounds the target's pixels in the
  // image, so a target that leaves the frame is `truncated` and its amodal box, unoccluded pixels and
  // dimensions count only its part inside the image.
  PixelBox modal_box, amodal_box;
  bool truncated = false;  // the amodal box touches the image's border
  uint64_t visible_pixels = 0, unoccluded_pixels = 0;
  // TTP's characteristic dimension: the square root of the target's unoccluded silhouette (pixels);
  // Johnson's critical dimension: the smaller side of its amodal box (pixels).
  double characteristic_dimension_px = 0, critical_dimension_px = 0;
  double visible_fraction() const {
    return unoccluded_pixels ? static_cast<double>(visible_pixels) / static_cast<double>(unoccluded_pixels) : 0.0;
  }
};

// Every target of `file` in `image` (a whole-image render holding id.object).
std::vector<TargetAnnotation> annotate_targets(const SceneFile& file, const Image& image, int threads);

// COCO's uncompressed RLE of a row-major mask: run lengths in column-major order, starting with
// a run of zeros (pycocotools' `counts` as a list; `size` is [height, width]).
std::vector<uint64_t> rle_counts(const std::vector<uint8_t>& mask, int width, int height);

}  // namespace sylva
