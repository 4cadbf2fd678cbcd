#include "pipeline/scene_request.h"

#include "core/error.h"

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

std::string SceneSource::label() const {
  if (!file.empty()) return file;
  return text.empty() ? "<default scene>" : name;
}

SceneFile load_scene(const SceneSource& source, const SceneOptions& options) {
  if (!source.file.empty()) return load_scene_file(source.file, options);
  if (!source.text.empty()) return parse_scene(source.text, source.name, ".", options);
  return default_scene(options);
}

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
  scene_options.overrides = request.overrides;
  scene_options.tree_memo = request.tree_memo;
  if (!request.res.empty()) scene_options.resolution = parse_resolution(request.res);
  RenderJob job{load_scene(request.source, scene_options), {}};
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
  if (request.noise_threshold >= 0) settings.noise_threshold = static_cast<float>(request.noise_threshold);
  if (!request.noise_channels.empty()) settings.noise_channels = split_list(request.noise_channels);
  if (request.time_limit_s >= 0) settings.time_limit_s = request.time_limit_s;
  settings.progress = request.progress;
  settings.features = settings.features || request.features;
  settings.material_ids = settings.material_ids || request.material_ids;
  return job;
}

std::map<std::string, std::string> describe_job(const RenderRequest& request, const RenderSettings& settings) {
  // A partial file names its scene so `sylva merge` can load it again; text has no name to give.
  if (request.source.file.empty() && !request.source.text.empty())
    throw Error("a chunk of a split render needs its scene in a file (sylva merge loads it again), not as text");
  const RenderSettings& s = settings;
  std::string bands;
  for (const Band& b : s.bands) bands += (bands.empty() ? "" : ",") + b.name;
  std::map<std::string, std::string> fields{
      {"scene",
       request.source.file.empty() ? "" : std::filesystem::absolute(request.source.file).lexically_normal().string()},
      {"res", fmt::format("{}x{}", s.width, s.height)},
      {"seed", std::to_string(s.seed)},
      {"max_depth", std::to_string(s.integrator.max_depth)},
      {"bands", bands},
      {"quantity", quantity_name(s.quantity)},
      {"isa", embree_isa_name(s.isa)}};
  // Hexadecimal: the exact double, so the merge rebuilds the same scene.
  if (s.features) fields.emplace("features", "yes");
  if (s.material_ids) fields.emplace("material_ids", "yes");
  if (s.noise_threshold > 0) {
    fields["noise_threshold"] = fmt::format("{:a}", static_cast<double>(s.noise_threshold));
    std::string channels;
    for (const auto& c : s.noise_channels) channels += (channels.empty() ? "" : ",") + c;
    if (!channels.empty()) fields["noise_channels"] = channels;
  }
  if (request.time_s) fields["time"] = fmt::format("{:a}", *request.time_s);
  for (size_t i = 0; i < request.overrides.size(); ++i) fields[fmt::format("set_{}", i)] = request.overrides[i];
  return fields;
}

RenderRequest request_from_job(const std::map<std::string, std::string>& fields, int spp) {
  RenderRequest r;
  r.source.file = field(fields, "scene");
  r.res = field(fields, "res");
  r.spp = spp;
  r.seed = to_int("seed", field(fields, "seed"));
  r.max_depth = static_cast<int>(to_int("max_depth", field(fields, "max_depth")));
  r.bands = field(fields, "bands");
  if (const auto it = fields.find("quantity"); it != fields.end()) r.quantity = it->second;
  if (const auto it = fields.find("isa"); it != fields.end()) r.isa = it->second;
  r.features = fields.count("features") > 0;
  r.material_ids = fields.count("material_ids") > 0;
  if (const auto it = fields.find("noise_threshold"); it != fields.end()) {
    char* end = nullptr;
    r.noise_threshold = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0') throw Error("partial render header: job.noise_threshold is not a number");
  }
  if (const auto it = fields.find("noise_channels"); it != fields.end()) r.noise_channels = it->second;
  for (size_t i = 0;; ++i) {
    const auto it = fields.find(fmt::format("set_{}", i));
    if (it == fields.end()) break;
    r.overrides.push_back(it->second);
  }
  if (const auto it = fields.find("time"); it != fields.end()) {
    char* end = nullptr;
    r.time_s = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0') throw Error("partial render header: job.time is not a number");
  }
  return r;
}

}  // namespace sylva
