// The compare's material regions (compare/regions.h) on real renders: with `id.material`
// (RenderSettings::material_ids) a bark reflectance +5 % on the golden aspen, which covers few
// pixels of the image, fails its material's region, while an unchanged scene with another seed
// passes. The renders are those of the golden suite's tree_aspen case at twice its resolution, a
// 256-spp reference against 64-spp tests (docs/compare.md, "Local tests").

#include "compare/image_compare.h"
#include "compare/regions.h"
#include "pipeline/render_call.h"
#include "render/scene.h"
#include "scenes/scene_file.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>

namespace sylva {
namespace material_regions_test {
namespace {

const std::string kAspen = SYLVA_SOURCE_DIR "/golden/scenes/tree_aspen.toml";

Image render_aspen(int spp, uint64_t seed, const std::function<void(Scene&)>& modify = {}) {
  RenderCallOptions o;
  o.request.source = SceneSource::from_file(kAspen);
  o.memory_check = false;
  o.seams.isa = EmbreeIsa::kAvx2;
  o.seams.modify_scene = modify;
  RenderObserver silent;
  const LoadedScene loaded = load_render(o, silent);
  return render_loaded(loaded, o, silent,
                       [&](RenderSettings& s) {
                         s.spp = spp;
                         s.seed = seed;
                         s.progress = false;
                         s.width *= 2;
                         s.height *= 2;
                         s.material_ids = true;
                       })
      .image;
}

// The bark material's label in id.material (its index + 1).
int64_t bark_label() {
  const Scene scene = load_scene_file(kAspen).scene;
  for (size_t m = 0; m < scene.material_names.size(); ++m)
    if (scene.material_names[m] == "bark") return static_cast<int64_t>(m) + 1;
  ADD_FAILURE() << "no bark material in " << kAspen;
  return -1;
}

const RegionTest* strongest_failure(const CompareResult& r) {
  const RegionTest* best = nullptr;
  for (const RegionTest& t : r.regions)
    if (t.failed() && (best == nullptr || t.bias_p_holm < best->bias_p_holm)) best = &t;
  return best;
}

TEST(MaterialRegions, BarkPlus5PercentFailsTheBarkRegion) {
  const Image ref = render_aspen(256, 1);
  ASSERT_GE(ref.find_channel("id.material"), 0);
  const int64_t bark = bark_label();

  const CompareResult same = compare_images(render_aspen(64, 2), ref, {});
  EXPECT_TRUE(same.passed) << format_compare_summary(same);

  const auto brighter_bark = [](Scene& s) {
    for (size_t m = 0; m < s.materials.size(); ++m)
      if (s.material_names[m] == "bark") std::get<DiffuseMaterial>(s.materials[m]).reflectance *= 1.05f;
  };
  const CompareResult r = compare_images(render_aspen(64, 3, brighter_bark), ref, {});
  EXPECT_FALSE(r.passed) << "bark +5 % was not caught: " << format_compare_summary(r);
  bool bark_failed = false;
  for (const RegionTest& t : r.regions) {
    if (t.kind != RegionKind::Material || t.label != bark) continue;
    bark_failed = bark_failed || t.failed();
    std::printf("[material regions] bark +5%%: %s %s: %lld px, bias z %+.1f, shift %+.2f%%\n", t.channel.c_str(),
                region_name(t).c_str(), static_cast<long long>(t.pixels), t.bias_z, 100.0 * t.mean_shift);
  }
  EXPECT_TRUE(bark_failed) << format_compare_summary(r);
  if (const RegionTest* t = strongest_failure(r))
    std::printf("[material regions] strongest failing region: %s %s (z %+.1f)\n", t->channel.c_str(),
                region_name(*t).c_str(), t->bias_z);
}

}  // namespace
}  // namespace material_regions_test
}  // namespace sylva
