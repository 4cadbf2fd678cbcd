// Issue 47's calibration of the statistical comparison (docs/compare.md, "Calibration";
// bench/golden_calibration.sh runs it):
//
//   sylva_golden_calibration false-alarms SCENE.toml PAIRS REF_SPP TEST_SPP [WxH|-] [set:KEY=VALUE[;...]]
//     PAIRS comparisons of two independent renders (a reference at REF_SPP and a test at TEST_SPP,
//     every seed new): how many fail at the default levels, and at a family α of 0.05.
//   sylva_golden_calibration power SCENE.toml FAULT[|FAULT] TRIALS REF_SPP SPP[,SPP] [WxH]
//     one reference of the unchanged scene, then TRIALS test renders with each FAULT at each SPP:
//     the share detected, the median |z| of the most significant failing region, and the last
//     detecting region. Faults: cab45-oak (Cab 40 → 45 on the default forest's oaks), cab40-oak
//     (its control: the oaks' own leaf at Cab 40), cab45-all (every leaf), bark+5%, nir-band (leaf
//     reflectance and transmittance +20 % within 840–850 nm), shadow-alpha (shadow rays ignore the
//     leaf outlines: on a scene with one tree, that tree's shadow), sky+3% (the whole sky),
//     horizon+3% (the sky below 15° elevation only: TransportFaults::sky_horizon_gain), none, and
//     set:KEY=VALUE[;KEY=VALUE] (overrides of the scene file, as `--set`).
//
// Renders run in this process through the render call (the scene loaded and its BVH built once per
// variant), with Embree's AVX2 kernels as the golden suite does. One line per comparison on stderr;
// a summary line (markdown table row) on stdout.

#include "compare/image_compare.h"
#include "core/error.h"
#include "core/spectrum.h"
#include "pipeline/render_call.h"
#include "render/scene.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace sylva {
namespace {

struct Fault {
  std::string name;
  std::vector<std::string> overrides;  // --set of the scene file
  std::function<void(Scene&)> modify;  // in memory, after loading
  TransportFaults transport;           // render/testing/faults.h
};

// Every leaf material's reflectance and transmittance × (1 + gain) within [lo, hi) nm.
std::function<void(Scene&)> leaf_band(float lo_nm, float hi_nm, float gain) {
  return [=](Scene& s) {
    for (Material& m : s.materials)
      if (auto* leaf = std::get_if<LeafMaterial>(&m))
        for (SpectrumTexture* t :
             {&leaf->reflectance_front, &leaf->reflectance_back, &leaf->transmittance_front, &leaf->transmittance_back})
          for (int i = 0; i < kLambdaSamples; ++i)
            if (const float l = DenseSpectrum::grid_lambda(i); l >= lo_nm && l < hi_nm) t->spectrum[i] *= 1.0f + gain;
  };
}

const std::string kLeaf = "{N = 1.5, Car = 8, Cw = 0.01, Cm = 0.009, Cab = ";

std::vector<Fault> faults() {
  std::vector<Fault> f;
  // The default forest's four species share one leaf: the oak (vegetation.species[2]) gets its own.
  f.push_back({"cab45-oak",
               {"materials.oak_leaf={type=\"leaf\", prospect=" + kLeaf + "45}}", "vegetation.species[2].leaf=oak_leaf"},
               {},
               {}});
  f.push_back({"cab40-oak",  // the control: the same material with the reference's Cab
               {"materials.oak_leaf={type=\"leaf\", prospect=" + kLeaf + "40}}", "vegetation.species[2].leaf=oak_leaf"},
               {},
               {}});
  f.push_back({"cab45-all", {"materials.leaf.prospect.Cab=45"}, {}, {}});
  f.push_back({"bark+5%",
               {"materials.bark.reflectance={file=\"spectra/helios_bark_wood_reflectance.csv\", "
                "column=\"bark_reflectivity_0000\", scale=1.05}"},
               {},
               {}});
  f.push_back({"nir-band", {}, leaf_band(840.0f, 850.0f, 0.2f), {}});
  f.push_back({"shadow-alpha", {}, {}, TransportFaults{.no_shadow_alpha = true}});
  f.push_back({"sky+3%", {}, [](Scene& s) { s.sky.spectrum *= 1.03f; }, {}});
  f.push_back({"horizon+3%", {}, {}, TransportFaults{.sky_horizon_gain = 1.03f, .sky_horizon_elevation_deg = 15.0f}});
  f.push_back({"none", {}, {}, {}});
  return f;
}

RenderCallOptions call_options(const std::string& scene, const Fault& fault) {
  RenderCallOptions o;
  o.request.source = SceneSource::from_file(scene);
  o.request.overrides = fault.overrides;
  o.memory_check = false;
  o.seams.isa = EmbreeIsa::kAvx2;
  o.seams.modify_scene = fault.modify;
  o.seams.faults = fault.transport;
  return o;
}

// A scene loaded (its BVH built) once and rendered many times. Built in place: the BVH refers to
// the loaded scene, which must not move.
struct Variant {
  Variant(const std::string& scene, const Fault& fault)
      : options(call_options(scene, fault)), loaded(load_render(options, silent)) {}
  RenderObserver silent;
  RenderCallOptions options;
  LoadedScene loaded;
};

Image render(const Variant& v, int spp, uint64_t seed, int width, int height) {
  RenderObserver silent;
  return render_loaded(v.loaded, v.options, silent,
                       [&](RenderSettings& s) {
                         s.spp = spp;
                         s.seed = seed;
                         s.progress = false;
                         s.material_ids = true;  // the material regions of the local tests
                         if (width > 0) {
                           s.width = width;
                           s.height = height;
                         }
                       })
      .image;
}

// sylva compare's defaults: channels with variance (bands, albedo) z-tested, ids exact, depth,
// normals and positions (no variance) left out.
CompareOptions options(double bias_alpha) {
  CompareOptions o;
  o.bias_alpha = bias_alpha;
  return o;
}

// The failing region of smallest Holm p: its kind and |z| (0 if none fails).
std::pair<std::string, double> strongest(const CompareResult& r) {
  const RegionTest* best = nullptr;
  for (const RegionTest& t : r.regions)
    if (t.failed() && (best == nullptr ||
                       std::min(t.bias_p_holm, t.variance_p_holm) < std::min(best->bias_p_holm, best->variance_p_holm)))
      best = &t;
  if (best == nullptr) return {r.passed ? "-" : "pixels", 0.0};
  return {fmt::format("{} {}", best->channel, region_name(*best)), std::abs(best->bias_z)};
}

// The region of largest |bias z| whether it fails or not, and the largest among material regions.
std::string largest_z(const CompareResult& r) {
  const RegionTest *any = nullptr, *material = nullptr;
  for (const RegionTest& t : r.regions) {
    if (any == nullptr || std::abs(t.bias_z) > std::abs(any->bias_z)) any = &t;
    if (t.kind == RegionKind::Material && (material == nullptr || std::abs(t.bias_z) > std::abs(material->bias_z)))
      material = &t;
  }
  std::string out;
  for (const RegionTest* t : {any, material})
    if (t != nullptr)
      out += fmt::format("{}{} {} z {:+.2f} ({} px, shift {:+.2f}%)", out.empty() ? "" : "; ", t->channel,
                         region_name(*t), t->bias_z, t->pixels, 100.0 * t->mean_shift);
  return out;
}

void parse_res(const char* text, int& w, int& h) {
  if (std::sscanf(text, "%dx%d", &w, &h) != 2) throw Error(std::string("bad resolution ") + text);
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, separator);) out.push_back(item);
  return out;
}

int false_alarms(int argc, char** argv) {
  const std::string scene = argv[2];
  const int pairs = std::atoi(argv[3]), ref_spp = std::atoi(argv[4]), test_spp = std::atoi(argv[5]);
  int w = 0, h = 0;
  if (argc > 6 && std::string(argv[6]) != "-") parse_res(argv[6], w, h);
  Fault settings{"none", {}, {}, {}};  // set:KEY=VALUE[;KEY=VALUE]: both renders' scene changed alike
  if (argc > 7 && std::string(argv[7]).rfind("set:", 0) == 0)
    settings.overrides = split(std::string(argv[7]).substr(4), ';');
  const Variant v(scene, settings);
  int fail_default = 0, fail_05 = 0, fail_pixels = 0;
  int64_t family = 0;
  for (int i = 0; i < pairs; ++i) {
    const Image ref = render(v, ref_spp, 1000003ull + 2ull * static_cast<uint64_t>(i), w, h);
    const Image test = render(v, test_spp, 1000004ull + 2ull * static_cast<uint64_t>(i), w, h);
    const CompareResult a = compare_images(test, ref, options(1e-3));
    const CompareResult b = compare_images(test, ref, options(0.05));
    fail_default += a.passed ? 0 : 1;
    fail_05 += b.passed ? 0 : 1;
    fail_pixels += a.reject_fraction > a.limit ? 1 : 0;
    family = a.family_size;
    fmt::print(stderr, "pair {}: default {} ({}), alpha 0.05 {} ({}), rejecting share {:.4f}%\n", i,
               a.passed ? "pass" : "FAIL", strongest(a).first, b.passed ? "pass" : "FAIL", strongest(b).first,
               100.0 * a.reject_fraction);
  }
  fmt::print("| {} | {} | {} vs {} | {} | {} / {} | {} / {} | {} |\n", scene, family, test_spp, ref_spp, pairs,
             fail_default, pairs, fail_05, pairs, fail_pixels);
  return 0;
}

// One fault at every spp against the shared reference: one table row per spp.
void power_of(const std::string& scene, const Fault& fault, int trials, const std::vector<int>& spps, const Image& ref,
              int w, int h) {
  const Variant v(scene, fault);
  for (const int spp : spps) {
    int detected = 0;
    std::vector<double> z;
    std::string where;
    for (int t = 0; t < trials; ++t) {
      const Image test = render(v, spp, 7000 + static_cast<uint64_t>(t), w, h);
      const CompareResult r = compare_images(test, ref, options(1e-3));
      detected += r.passed ? 0 : 1;
      const auto [region, zs] = strongest(r);
      z.push_back(zs);
      if (!r.passed) where = region;
      fmt::print(stderr, "{} {} spp trial {}: {} ({}, |z| {:.2f}), whole-image bias z {:+.2f}; largest: {}\n",
                 fault.name, spp, t, r.passed ? "pass" : "FAIL", region, zs,
                 r.channels.empty() ? 0.0 : r.channels.front().bias_z, largest_z(r));
    }
    std::sort(z.begin(), z.end());
    fmt::print("| {} | {} | {} | {} / {} | {:.1f} | {} |\n", fault.name, scene, spp, detected, trials, z[z.size() / 2],
               where.empty() ? "-" : where);
    std::fflush(stdout);
  }
}

int power(int argc, char** argv) {
  const std::string scene = argv[2];
  const int trials = std::atoi(argv[4]), ref_spp = std::atoi(argv[5]);
  std::vector<int> spps;
  for (const std::string& s : split(argv[6], ',')) spps.push_back(std::atoi(s.c_str()));
  int w = 0, h = 0;
  if (argc > 7) parse_res(argv[7], w, h);
  const std::vector<Fault> all = faults();
  std::vector<Fault> chosen;
  for (const std::string& name : split(argv[3], '|')) {
    if (name.rfind("set:", 0) == 0) {  // set:KEY=VALUE[;KEY=VALUE]: overrides of the scene file
      Fault f{name, {}, {}, {}};
      std::stringstream in(name.substr(4));
      for (std::string item; std::getline(in, item, ';');) f.overrides.push_back(item);
      chosen.push_back(f);
      continue;
    }
    const auto f = std::find_if(all.begin(), all.end(), [&](const Fault& x) { return x.name == name; });
    if (f == all.end()) throw Error("unknown fault " + name);
    chosen.push_back(*f);
  }
  const Image ref = render(Variant(scene, Fault{}), ref_spp, 1, w, h);
  for (const Fault& f : chosen) power_of(scene, f, trials, spps, ref, w, h);
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "false-alarms" && argc >= 6) return sylva::false_alarms(argc, argv);
    if (mode == "power" && argc >= 7) return sylva::power(argc, argv);
    fmt::print(stderr,
               "usage: {0} false-alarms SCENE PAIRS REF_SPP TEST_SPP [WxH|-] [set:KEY=VALUE[;...]]\n"
               "       {0} power SCENE FAULT[|FAULT] TRIALS REF_SPP SPP[,SPP] [WxH]\n",
               argc > 0 ? argv[0] : "sylva_golden_calibration");
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
}
