#include "core/color.h"

#include "core/data_path.h"
#include "core/error.h"

#include <OpenColorIO/OpenColorIO.h>

#include <map>
#include <mutex>

namespace OCIO = OCIO_NAMESPACE;

namespace sylva {
namespace {

std::filesystem::path resolve(const std::filesystem::path& config) {
  return config.empty() ? data_file("ocio/config.ocio") : config;
}

OCIO::ConstConfigRcPtr load_config(const std::filesystem::path& config) {
  static std::mutex mutex;
  static std::map<std::filesystem::path, OCIO::ConstConfigRcPtr> cache;
  const std::filesystem::path path = resolve(config);
  const std::lock_guard lock(mutex);
  if (auto it = cache.find(path); it != cache.end()) return it->second;
  if (!std::filesystem::exists(path)) throw Error(path.string() + ": OCIO config not found");
  try {
    OCIO::ConstConfigRcPtr loaded = OCIO::Config::CreateFromFile(path.c_str());
    loaded->validate();
    if (loaded->getNumViews(std::string(preview_display).c_str()) == 0)
      throw Error(path.string() + ": OCIO config has no display \"" + std::string(preview_display) + "\"");
    cache.emplace(path, loaded);
    return loaded;
  } catch (const OCIO::Exception& e) {
    throw Error(path.string() + ": invalid OCIO config: " + e.what());
  }
}

}  // namespace

void validate_ocio_config(const std::filesystem::path& config) { load_config(config); }

std::vector<std::string> ocio_views(const std::filesystem::path& config) {
  const OCIO::ConstConfigRcPtr cfg = load_config(config);
  const std::string display(preview_display);
  std::vector<std::string> views;
  for (int i = 0; i < cfg->getNumViews(display.c_str()); ++i) views.emplace_back(cfg->getView(display.c_str(), i));
  return views;
}

void check_preview_view(std::string_view view, const std::filesystem::path& config) {
  const std::vector<std::string> views = ocio_views(config);
  bool known = false;
  std::string list;
  for (const std::string& v : views) {
    known = known || v == view;
    list += (list.empty() ? "" : ", ") + v;
  }
  if (!known) throw Error("unknown preview view \"" + std::string(view) + "\" (available: " + list + ")");
}

void apply_display_transform(float* rgb, size_t pixel_count, std::string_view view,
                             const std::filesystem::path& config) {
  const OCIO::ConstConfigRcPtr cfg = load_config(config);
  check_preview_view(view, config);
  if (pixel_count == 0) return;
  try {
    OCIO::DisplayViewTransformRcPtr transform = OCIO::DisplayViewTransform::Create();
    transform->setSrc(OCIO::ROLE_SCENE_LINEAR);
    transform->setDisplay(std::string(preview_display).c_str());
    transform->setView(std::string(view).c_str());
    OCIO::ConstCPUProcessorRcPtr cpu = cfg->getProcessor(transform)->getDefaultCPUProcessor();
    // One row of pixel_count pixels; OCIO takes long sizes.
    OCIO::PackedImageDesc desc(rgb, static_cast<long>(pixel_count), 1, 3);
    cpu->apply(desc);
  } catch (const OCIO::Exception& e) {
    throw Error(std::string("OCIO display transform failed: ") + e.what());
  }
}

}  // namespace sylva
