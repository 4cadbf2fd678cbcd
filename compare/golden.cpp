#include "compare/golden.h"

#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "pipeline/render_call.h"
#include "scenes/toml_reader.h"

#include <fmt/core.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

namespace sylva {

std::vector<GoldenCase> list_golden_cases(const std::filesystem::path& golden_dir) {
  std::vector<GoldenCase> cases;
  const auto scenes = golden_dir / "scenes";
  if (!std::filesystem::is_directory(scenes)) throw Error(scenes.string() + ": no golden scenes directory");
  for (const auto& e : std::filesystem::directory_iterator(scenes)) {
    if (e.path().extension() != ".toml") continue;
    const std::string name = e.path().stem().string();
    cases.push_back({name, e.path(), golden_dir / (name + ".exr"), golden_dir / (name + ".toml")});
  }
  std::sort(cases.begin(), cases.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return cases;
}

GoldenRecord read_golden_record(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file))
    throw ParseError(file, 0, "cannot open golden record (run `sylva golden update`)");
  TomlReader r(file.string());
  const toml::table t = r.parse(read_input_file(file, kMaxSceneFileBytes, "golden record"));
  r.check_keys(t,
               {"reference_spp", "reference_seed", "check_spp", "check_seed", "determinism_spp", "determinism_seed",
                "determinism_hash", "scene_hash", "version"},
               "a golden record");
  GoldenRecord g;
  g.reference_spp = static_cast<int>(r.integer(t, "reference_spp", g.reference_spp, 1, 1 << 24));
  g.reference_seed = static_cast<uint64_t>(r.integer(t, "reference_seed", 1, 0, INT64_MAX));
  g.check_spp = static_cast<int>(r.integer(t, "check_spp", g.check_spp, 1, 1 << 24));
  g.check_seed = static_cast<uint64_t>(r.integer(t, "check_seed", 2, 0, INT64_MAX));
  g.determinism_spp = static_cast<int>(r.integer(t, "determinism_spp", g.determinism_spp, 1, 1 << 16));
  g.determinism_seed = static_cast<uint64_t>(r.integer(t, "determinism_seed", 3, 0, INT64_MAX));
  g.determinism_hash = r.string(t, "determinism_hash");
  g.scene_hash = r.string(t, "scene_hash", "");
  g.version = r.string(t, "version", "");
  return g;
}

void write_golden_record(const std::filesystem::path& file, const GoldenRecord& g) {
  write_text_file(file, fmt::format("# Written by `sylva golden update`; see golden/README.md.\n"
                                    "reference_spp = {}\nreference_seed = {}\ncheck_spp = {}\ncheck_seed = {}\n"
                                    "determinism_spp = {}\ndeterminism_seed = {}\ndeterminism_hash = \"{}\"\n"
                                    "scene_hash = \"{}\"\nversion = \"{}\"\n",
                                    g.reference_spp, g.reference_seed, g.check_spp, g.check_seed, g.determinism_spp,
                                    g.determinism_seed, g.determinism_hash, g.scene_hash, g.version));
}

namespace {

// Removes `names` (those present) from `image`.
void drop_channels(Image& image, const std::vector<std::string>& names) {
  std::vector<int> keep;
  for (int c = 0; c < image.channel_count(); ++c)
    if (std::find(names.begin(), names.end(), image.channels[static_cast<size_t>(c)]) == names.end()) keep.push_back(c);
  Image out = image;
  out.channels.clear();
  out.types.clear();
  out.pixels.clear();
  for (int c : keep) {
    out.channels.push_back(image.channels[static_cast<size_t>(c)]);
    out.types.push_back(image.types[static_cast<size_t>(c)]);
  }
  out.pixels.reserve(size_t(image.width) * size_t(image.height) * keep.size());
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c : keep) out.pixels.push_back(image.at(x, y, c));
  image = std::move(out);
}

}  // namespace

std::string image_hash(const Image& image) {
  Fnv1a64 h;
  h.add(&image.width, sizeof(image.width));
  h.add(&image.height, sizeof(image.height));
  for (const std::string& c : image.channels) h.add(c.c_str(), c.size() + 1);  // with the terminating 0
  h.add_vector(image.pixels);
  return hex64(h.value());
}

namespace {

// A golden case through the render call: its scene file, in memory, with the reference BVH build
// and Embree's AVX2 kernels (kGoldenIsa), and the power tests' seams.
RenderCallOptions golden_call(const GoldenCase& c, const std::function<void(Scene&)>& modify = {},
                              const TransportFaults& faults = {}) {
  RenderCallOptions o;
  o.request.source = SceneSource::from_file(c.scene.string());
  o.memory_check = false;
  o.seams.bvh = BvhBuild::kThorough;
  o.seams.isa = kGoldenIsa;
  o.seams.modify_scene = modify;
  o.seams.faults = faults;
  return o;
}

// One image of a loaded case at `spp` and `seed`; `adjust` may change the settings further.
Image render_golden(const LoadedScene& loaded, const RenderCallOptions& options, int spp, uint64_t seed,
                    const std::function<void(RenderSettings&)>& adjust = {}) {
  RenderObserver silent;
  return render_loaded(loaded, options, silent,
                       [&](RenderSettings& s) {
                         s.spp = spp;
                         s.seed = seed;
                         if (adjust) adjust(s);
                       })
      .image;
}

}  // namespace

CompareOptions golden_compare_options() {
  CompareOptions o;
  o.abs_tolerances = {{"Z", 1e-3}, {"N.X", 2e-3}, {"N.Y", 2e-3}, {"N.Z", 2e-3}};
  return o;
}

void update_golden_case(const GoldenCase& c, const GoldenRecord& settings, bool progress) {
  GoldenRecord g = settings;
  RenderCallOptions options = golden_call(c);
  RenderObserver silent;
  const LoadedScene loaded = load_render(options, silent);  // one BVH for both renders
  options.progress_bar = progress;
  const Image ref = render_golden(loaded, options, g.reference_spp, g.reference_seed,
                                  [&](RenderSettings& s) { s.progress = progress; });
  const Image det = render_golden(loaded, options, g.determinism_spp, g.determinism_seed,
                                  [](RenderSettings& s) { s.progress = false; });
  g.determinism_hash = image_hash(det);
  g.scene_hash = loaded.job.file.content_hash;
  g.version = SYLVA_VERSION;
  write_exr(c.reference, ref);
  write_golden_record(c.record, g);
}

GoldenCheck check_golden_case(const GoldenCase& c, const std::function<void(RenderSettings&)>& adjust,
                              const std::function<void(Scene&)>& modify, const TransportFaults& faults,
                              const std::vector<std::string>& overrides) {
  const GoldenRecord g = read_golden_record(c.record);
  const Image ref = read_exr(c.reference);
  GoldenCheck out;
  RenderCallOptions options = golden_call(c, modify, faults);
  options.request.overrides = overrides;
  RenderObserver silent;
  const LoadedScene loaded = load_render(options, silent);  // one BVH for both renders
  // The hash is the file's (and its inputs'): the power tests' change to the scene does not enter it.
  const std::string& scene_hash = loaded.job.file.content_hash;
  if (overrides.empty() && !g.scene_hash.empty() && g.scene_hash != scene_hash)
    throw Error(
        fmt::format("{}: the scene changed since its reference was rendered (hash {} vs {}); review it and "
                    "run `sylva golden update --only {}`",
                    c.scene.string(), scene_hash, g.scene_hash, c.name));
  out.test = render_golden(loaded, options, g.check_spp, g.check_seed, adjust);
  // A reference rendered before an AOV existed is compared on the channels it has; a reference
  // with the position AOV checks it like depth.
  CompareOptions compare = golden_compare_options();
  if (ref.find_channel("P.X") < 0) {
    drop_channels(out.test, {"P.X", "P.Y", "P.Z"});
  } else {
    for (const char* ch : {"P.X", "P.Y", "P.Z"}) compare.abs_tolerances.emplace_back(ch, 1e-3);
  }
  // The label AOVs id.class and id.variant (issue 9): a reference without them keeps its record,
  // so its determinism hash is taken over the channels it was recorded with.
  const bool without_labels = ref.find_channel("id.class") < 0;
  const std::vector<std::string> labels{"id.class", "id.variant"};
  if (without_labels) drop_channels(out.test, labels);
  AssumptionOptions intended;
  intended.allowed =
      modify || !overrides.empty() ? std::vector<std::string>{"all"} : std::vector<std::string>{"scene", "sampler"};
  out.assumptions = check_assumptions(out.test, ref, intended);
  if (out.assumptions.refused())
    throw RefusedComparison(fmt::format("{}: refused: {}", c.name, out.assumptions.refusal()));
  out.compare = compare_images(out.test, ref, compare);
  Image det = render_golden(loaded, options, g.determinism_spp, g.determinism_seed, adjust);
  if (without_labels) drop_channels(det, labels);
  out.determinism_hash = image_hash(det);
  out.determinism_checked = overrides.empty();
  out.determinism_matches = out.determinism_hash == g.determinism_hash;
  return out;
}

}  // namespace sylva
