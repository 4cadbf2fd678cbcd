#pragma once
// Coverage of single instances without occluders: for the JSON sidecar's occlusion figures
// (scenes/sidecar.h), how many pixels an instance would cover if nothing else were in the scene.
// The rays are the first-hit AOVs' rays (Renderer::make_image: a pinhole ray through each pixel
// centre), so a pixel whose `id.object` shows the instance is always counted here too.

#include "render/scene.h"

#include <cstdint>
#include <vector>

namespace sylva {

// Per entry of `instances` (indices into scene.instances): the number of pixels of a width × height
// image whose centre ray hits that instance alone. One small Embree scene per instance (its
// prototype and transform only).
std::vector<uint64_t> unoccluded_pixels(const Scene& scene, const std::vector<uint32_t>& instances, int width,
                                        int height, int threads);

}  // namespace sylva
