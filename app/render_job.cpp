#include "app/render_job.h"

#include "scenes/sidecar.h"

#include "core/error.h"
#include "core/image.h"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tuple>

namespace sylva {

namespace {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= s.size()) {
    const size_t end = s.find(',', start);
    std::string item = s.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!item.empty()) out.push_back(item);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

// Exposure for the preview: the median luminance of the visible band maps to 18% grey.
float auto_exposure_ev(const Image& image, const std::array<std::string, 3>& channels) {
  const int r = image.find_channel(channels[0]), g = image.find_channel(channels[1]),
            b = image.find_channel(channels[2]);
  std::vector<float> lum;
  lum.reserve(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float l = 0.2126f * image.at(x, y, r) + 0.7152f * image.at(x, y, g) + 0.0722f * image.at(x, y, b);
      if (l > 0 && std::isfinite(l)) lum.push_back(l);
    }
  if (lum.empty()) return 0.0f;
  std::nth_element(lum.begin(), lum.begin() + lum.size() / 2, lum.end());
  return std::log2(0.18f / lum[lum.size() / 2]);
}

const std::string& field(const std::map<std::string, std::string>& fields, const std::string& name) {
  const auto it = fields.find(name);
  if (it == fields.end()) throw Error("partial render header lacks job." + name);
  return it->second;
}

int64_t to_int(const std::string& name, const std::string& value) {
  char* end = nullptr;
  const long long v = std::strtoll(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0') throw Error("partial render header: job." + name + " is not an integer");
  return v;
}

}  // namespace

std::pair<int, int> parse_resolution(const std::string& text) {
  const size_t x = text.find('x');
  int w = 0, h = 0;
  const auto parse = [&](const char* first, const char* last, int& v) {
    const auto [ptr, ec] = std::from_chars(first, last, v);
    return ec == std::errc() && ptr == last && first != last && v >= 1 && v <= kMaxImageSide;
  };
  if (x == std::string::npos || !parse(text.data(), text.data() + x, w) ||
      !parse(text.data() + x + 1, text.data() + text.size(), h))
    throw Error(fmt::format("--res: expected WIDTHxHEIGHT with sides from 1 to {}, e.g. 1280x720, not '{}'",
                            kMaxImageSide, text));
  return {w, h};
}

RenderJob prepare_render(const RenderRequest& request) {
  SceneOptions scene_options;
  scene_options.time_s = request.time_s;
  if (!request.res.empty()) scene_options.resolution = parse_resolution(request.res);
  RenderJob job{request.scene.empty() ? default_scene(scene_options) : load_scene_file(request.scene, scene_options),
                {}};
  // The scene file's settings, with the command line's overrides on top.
  RenderSettings& settings = job.settings;
  settings = render_settings(job.file);
  if (request.spp > 0) settings.spp = request.spp;
  if (request.seed >= 0) settings.seed = static_cast<uint64_t>(request.seed);
  settings.threads = request.threads;
  if (request.max_depth > 0) settings.integrator.max_depth = request.max_depth;
  if (!request.quantity.empty()) settings.quantity = parse_quantity(request.quantity);
  if (!request.isa.empty()) settings.isa = parse_embree_isa(request.isa);
  if (!request.bands.empty()) settings.bands = resolve_bands(job.file, split_list(request.bands));
  settings.progress = request.progress;
  return job;
}

std::map<std::string, std::string> describe_job(const RenderRequest& request, const RenderJob& job) {
  const RenderSettings& s = job.settings;
  std::string bands;
  for (const Band& b : s.bands) bands += (bands.empty() ? "" : ",") + b.name;
  std::map<std::string, std::string> fields{
      {"scene", request.scene.empty() ? "" : std::filesystem::absolute(request.scene).lexically_normal().string()},
      {"res", fmt::format("{}x{}", s.width, s.height)},
      {"seed", std::to_string(s.seed)},
      {"max_depth", std::to_string(s.integrator.max_depth)},
      {"bands", bands},
      {"quantity", quantity_name(s.quantity)},
      {"isa", embree_isa_name(s.isa)}};
  // Hexadecimal: the exact double, so the merge rebuilds the same scene.
  if (request.time_s) fields["time"] = fmt::format("{:a}", *request.time_s);
  return fields;
}

RenderRequest request_from_job(const std::map<std::string, std::string>& fields, int spp) {
  RenderRequest r;
  r.scene = field(fields, "scene");
  r.res = field(fields, "res");
  r.spp = spp;
  r.seed = to_int("seed", field(fields, "seed"));
  r.max_depth = static_cast<int>(to_int("max_depth", field(fields, "max_depth")));
  r.bands = field(fields, "bands");
  if (const auto it = fields.find("quantity"); it != fields.end()) r.quantity = it->second;
  if (const auto it = fields.find("isa"); it != fields.end()) r.isa = it->second;
  if (const auto it = fields.find("time"); it != fields.end()) {
    char* end = nullptr;
    r.time_s = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0') throw Error("partial render header: job.time is not a number");
  }
  return r;
}

void write_render_outputs(const Renderer& renderer, const Film& film, const RenderJob& job,
                          const std::filesystem::path& exr, const std::filesystem::path& png,
                          const PreviewOverrides& overrides) {
  Image image = renderer.make_image(film);
  annotate_render(image, job.file, job.settings);
  write_exr(exr, image);
  write_sidecar(sidecar_path(exr), job.file, job.settings, image, exr);
  if (png.empty()) return;
  write_render_preview(renderer, image, job.file.output, png, overrides);
}

void write_render_preview(const Renderer& renderer, const Image& image, const OutputSection& output,
                          const std::filesystem::path& png, const PreviewOverrides& overrides) {
  PreviewOptions preview;
  if (image.find_channel("R") < 0) {
    const std::string grey = renderer.radiance_channels().front();
    preview.channels = {grey, grey, grey};
  }
  preview.view = overrides.view.empty() ? output.view : overrides.view;
  preview.exposure_ev = overrides.exposure_ev.value_or(output.exposure_ev) +
                        (output.auto_exposure ? auto_exposure_ev(image, preview.channels) : 0.0f);
  write_png_preview(png, image, preview);
}

}  // namespace sylva
