#include "render/coverage.h"

#include "render/embree_scene.h"
#include "render/sensors/camera.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <functional>

namespace sylva {

std::vector<uint64_t> unoccluded_pixels(const Scene& scene, const std::vector<uint32_t>& instances, int width,
                                        int height, int threads) {
  std::vector<uint64_t> out;
  const Camera camera(scene.camera, width, height);
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  for (const uint32_t index : instances) {
    const Instance& inst = scene.instances.at(index);
    Scene alone;
    alone.camera = scene.camera;
    alone.prototypes.push_back(scene.prototypes.at(inst.prototype));
    Instance copy = inst;
    copy.prototype = 0;
    alone.instances.push_back(copy);
    const EmbreeScene embree(alone);
    tbb::combinable<uint64_t> count(uint64_t{0});
    arena.execute([&] {
      tbb::parallel_for(0, height, [&](int y) {
        uint64_t row = 0;
        for (int x = 0; x < width; ++x) {
          const Ray ray = camera.generate_ray(Vec2(x + 0.5f, y + 0.5f), Vec2(0.5f));
          RayHit hit;
          if (embree.intersect(ray, &hit)) ++row;
        }
        count.local() += row;
      });
    });
    out.push_back(count.combine(std::plus<>()));
  }
  return out;
}

}  // namespace sylva
