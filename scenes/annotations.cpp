#include "scenes/annotations.h"

#include "core/error.h"
#include "render/embree_scene.h"
#include "render/sensors/camera.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

namespace sylva {

namespace {

void extend_box(PixelBox& b, int x, int y) {
  if (b.empty()) {
    b = {x, y, x, y};
    return;
  }
  b.x0 = std::min(b.x0, x);
  b.y0 = std::min(b.y0, y);
  b.x1 = std::max(b.x1, x);
  b.y1 = std::max(b.y1, y);
}

// The pixels whose centre ray (the label AOVs' rays) meets `instance` when it is alone.
std::vector<uint8_t> alone_mask(const Scene& scene, uint32_t instance, int width, int height, int threads) {
  const Camera camera(scene.camera, width, height);
  const Instance& inst = scene.instances.at(instance);
  Scene alone;
  alone.camera = scene.camera;
  alone.prototypes.push_back(scene.prototypes.at(inst.prototype));
  Instance copy = inst;
  copy.prototype = 0;
  alone.instances.push_back(copy);
  const EmbreeScene embree(alone);
  std::vector<uint8_t> mask(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(0, height, [&](int y) {
      for (int x = 0; x < width; ++x) {
        const Ray ray =
            camera.generate_ray(Vec2(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f), Vec2(0.5f));
        RayHit hit;
        mask[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] =
            embree.intersect(ray, &hit);
      }
    });
  });
  return mask;
}

}  // namespace

std::vector<TargetAnnotation> annotate_targets(const SceneFile& file, const Image& image, int threads) {
  const int object = image.find_channel("id.object");
  if (object < 0) throw Error("annotations need the id.object AOV");
  std::vector<TargetAnnotation> out;
  for (size_t i = 0; i < file.targets.size(); ++i) {
    const TargetInfo& t = file.targets[i];
    TargetAnnotation a;
    a.target = i;
    a.name = t.name;
    a.label = file.scene.class_names.at(t.class_id);
    a.object_id = t.object_id;
    a.class_id = t.class_id;
    a.modal.assign(static_cast<size_t>(image.width) * static_cast<size_t>(image.height), 0);
    const std::vector<uint8_t> amodal = alone_mask(file.scene, t.instance, image.width, image.height, threads);
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        const size_t k = static_cast<size_t>(y) * static_cast<size_t>(image.width) + static_cast<size_t>(x);
        if (image.at(x, y, object) == static_cast<float>(t.object_id)) {
          a.modal[k] = 1;
          ++a.visible_pixels;
          extend_box(a.modal_box, x, y);
        }
        if (amodal[k] != 0) {
          ++a.unoccluded_pixels;
          extend_box(a.amodal_box, x, y);
        }
      }
    const PixelBox& m = a.amodal_box;
    a.truncated = !m.empty() && (m.x0 == 0 || m.y0 == 0 || m.x1 == image.width - 1 || m.y1 == image.height - 1);
    a.characteristic_dimension_px = std::sqrt(static_cast<double>(a.unoccluded_pixels));
    a.critical_dimension_px = std::min(a.amodal_box.width(), a.amodal_box.height());
    out.push_back(std::move(a));
  }
  return out;
}

std::vector<uint64_t> rle_counts(const std::vector<uint8_t>& mask, int width, int height) {
  std::vector<uint64_t> counts;
  uint8_t current = 0;
  uint64_t run = 0;
  for (int x = 0; x < width; ++x)
    for (int y = 0; y < height; ++y) {
      const uint8_t v = mask[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] != 0;
      if (v != current) {
        counts.push_back(run);
        run = 0;
        current = v;
      }
      ++run;
    }
  counts.push_back(run);
  return counts;
}

}  // namespace sylva
