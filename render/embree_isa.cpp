// Embree's instruction sets and the BVH build quality (render/embree_scene.h).

#include "core/error.h"
#include "render/embree_scene.h"

#include <embree3/rtcore.h>
#include <fmt/core.h>

#include <algorithm>

namespace sylva {

BvhBuild bvh_build_for(uint64_t path_samples) {
  // About a minute of rendering on two cores: the thorough build's extra seconds pay for themselves.
  constexpr uint64_t kThoroughFrom = uint64_t{1} << 24;
  return path_samples >= kThoroughFrom ? BvhBuild::kThorough : BvhBuild::kFast;
}

namespace {

struct IsaName {
  EmbreeIsa isa;
  const char* name;
};
constexpr IsaName kIsaNames[] = {{EmbreeIsa::kNative, "native"}, {EmbreeIsa::kSse2, "sse2"},
                                 {EmbreeIsa::kSse42, "sse4.2"},  {EmbreeIsa::kAvx, "avx"},
                                 {EmbreeIsa::kAvx2, "avx2"},     {EmbreeIsa::kAvx512, "avx512"}};

// The widest set of Embree's kernels this processor runs (Embree's own feature tests).
EmbreeIsa processor_isa() {
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
                    __builtin_cpu_supports("bmi2");
  if (avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl"))
    return EmbreeIsa::kAvx512;
  if (avx2) return EmbreeIsa::kAvx2;
  if (__builtin_cpu_supports("avx")) return EmbreeIsa::kAvx;
  if (__builtin_cpu_supports("sse4.2")) return EmbreeIsa::kSse42;
  return EmbreeIsa::kSse2;
}

}  // namespace

EmbreeIsa parse_embree_isa(const std::string& name) {
  for (const IsaName& n : kIsaNames)
    if (name == n.name) return n.isa;
  throw Error(fmt::format(
      "unknown instruction set '{}': expected \"native\", \"sse2\", \"sse4.2\", \"avx\", \"avx2\" or \"avx512\"",
      name));
}

std::vector<std::string> embree_isa_names() {
  std::vector<std::string> names;
  for (const IsaName& n : kIsaNames) names.emplace_back(n.name);
  return names;
}

const char* embree_isa_name(EmbreeIsa isa) {
  for (const IsaName& n : kIsaNames)
    if (isa == n.isa) return n.name;
  return "native";
}

EmbreeIsa resolve_embree_isa(EmbreeIsa requested) {
  static const EmbreeIsa widest = [] {
    EmbreeIsa isa = processor_isa();
    // Embree's own word on the widths it runs: a library built without its AVX-512 (or AVX)
    // kernels falls back to the next it has.
    RTCDevice device = rtcNewDevice("verbose=0");
    if (!device) return isa;
    if (isa == EmbreeIsa::kAvx512 && !rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED))
      isa = EmbreeIsa::kAvx2;
    if (isa >= EmbreeIsa::kAvx && !rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED))
      isa = EmbreeIsa::kSse42;
    rtcReleaseDevice(device);
    return isa;
  }();
  return requested == EmbreeIsa::kNative ? widest : std::min(requested, widest);
}

}  // namespace sylva
