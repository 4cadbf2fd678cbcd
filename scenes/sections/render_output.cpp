#include "scenes/sections/render_output.h"

#include "core/error.h"

#include <cstdint>
#include <tuple>

namespace sylva {

static InstanceLevel parse_instancing(const Params& t) {
  const std::string instancing = t.string("instancing", "auto");
  if (instancing == "auto") return InstanceLevel::automatic;
  if (instancing == "native") return InstanceLevel::native;
  if (instancing == "array") return InstanceLevel::array;
  if (instancing == "sweep") return InstanceLevel::sweep;
  t.fail("instancing", "instancing must be \"auto\", \"native\", \"array\" or \"sweep\"");
}

void parse_render(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("render");
  t->check_keys({"width", "height", "spp", "seed", "max_depth", "bands", "quantity", "instancing", "isa", "sampler",
                 "noise_threshold", "noise_channels", "pilot_spp", "time_limit", "light_samples"});
  SceneFile& out = b.file();
  RenderSettings& rs = out.render;
  rs.width = static_cast<int>(t->integer("width", rs.width, 1, 65536));
  rs.height = static_cast<int>(t->integer("height", rs.height, 1, 65536));
  rs.spp = static_cast<int>(t->integer("spp", rs.spp, 1, 1 << 24));
  rs.seed = static_cast<uint64_t>(t->integer("seed", static_cast<int64_t>(rs.seed), 0, INT64_MAX));
  rs.integrator.max_depth = static_cast<int>(t->integer("max_depth", rs.integrator.max_depth, 1, 1024));
  rs.integrator.light_samples =
      static_cast<int>(t->integer("light_samples", rs.integrator.light_samples, 1, kMaxLightSamples));
  if (t->has("bands")) {
    out.bands = t->strings("bands");
    if (out.bands.empty()) t->fail("bands", "'bands' needs at least one band, e.g. [\"rgb\", \"nir\"]");
    for (size_t i = 0; i < out.bands.size(); ++i)
      for (size_t j = 0; j < i; ++j)
        if (out.bands[i] == out.bands[j]) t->fail("bands", "band '" + out.bands[i] + "' is listed twice");
  }
  const std::string quantity = t->string("quantity", quantity_name(rs.quantity));
  if (quantity != "radiance" && quantity != "reflectance")
    t->fail("quantity", "quantity must be \"radiance\" or \"reflectance\"");
  rs.quantity = parse_quantity(quantity);
  const std::string sampler = t->string("sampler", sampler_name(rs.sampler));
  if (sampler != "sobol" && sampler != "independent")
    t->fail("sampler", "sampler must be \"sobol\" (the default) or \"independent\"");
  rs.sampler = sampler == "sobol" ? SamplerKind::kSobol : SamplerKind::kIndependent;
  rs.noise_threshold = static_cast<float>(t->real("noise_threshold", rs.noise_threshold, 0.0, 0.999));
  if (t->has("noise_channels")) rs.noise_channels = t->strings("noise_channels");
  rs.pilot_spp = static_cast<int>(t->integer("pilot_spp", rs.pilot_spp, 4, 1 << 24));
  if (rs.pilot_spp % 2 != 0) t->fail("pilot_spp", "pilot_spp must be even (half of it in each of two streams)");
  rs.time_limit_s = t->real("time_limit", rs.time_limit_s, 0.0, 1e9);
  if (t->has("isa")) {
    try {
      rs.isa = parse_embree_isa(t->string("isa", embree_isa_name(rs.isa)));
    } catch (const Error& e) {
      t->fail("isa", e.what());
    }
  }
  out.scene.instance_level = parse_instancing(*t);
  // `--res` replaces the file's width and height (after they are checked).
  if (b.options().resolution) std::tie(rs.width, rs.height) = *b.options().resolution;
}

void parse_bands(const Params& root, SceneBuilder& b) {
  for (const Params* t : root.tables("bands")) {
    t->check_keys({"name", "response"});
    const std::string name = t->string("name");
    if (name.empty() || name.find_first_of(" .,") != std::string::npos)
      t->fail("name", "band name must be non-empty without spaces, dots or commas");
    if (!t->has("response")) t->fail("[[bands]] needs a response spectrum");
    const DenseSpectrum response = t->spectrum("response", Extrapolate::Zero);
    try {
      b.file().custom_bands.push_back(make_srf_band(name, response));
    } catch (const ParseError&) {
      throw;
    } catch (const Error& e) {
      t->fail("response", e.what());
    }
  }
}

void parse_output(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("output");
  t->check_keys({"exr", "png", "exposure", "auto_exposure", "view"});
  OutputSection& o = b.file().output;
  if (t->has("exr")) o.exr = t->string("exr");
  if (t->has("png")) o.png = t->string("png");
  o.exposure_ev = t->real("exposure", 0.0, -64.0, 64.0);
  o.auto_exposure = t->boolean("auto_exposure", true);
  o.view = t->string("view", o.view);
}

void parse_sensor(const Params& root, SceneBuilder& b) { b.file().sensor = read_sensor_params(*root.table("sensor")); }

}  // namespace sylva
