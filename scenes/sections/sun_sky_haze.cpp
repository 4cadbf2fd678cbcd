#include "scenes/sections/sun_sky_haze.h"

#include "core/registry.h"

#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <variant>

namespace sylva {

void parse_sun(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("sun");
  t->check_keys({"enabled", "azimuth", "elevation", "angular_radius", "irradiance", "scale"});
  SunDesc& s = b.scene().sun;
  s.enabled = t->boolean("enabled", true);
  s.azimuth_deg = t->real("azimuth", s.azimuth_deg, -360.0, 360.0);
  s.elevation_deg = t->real("elevation", s.elevation_deg, -90.0, 90.0);
  s.angular_radius_deg = t->real("angular_radius", s.angular_radius_deg, 1e-3, 10.0);
  if (t->has("irradiance")) s.irradiance = t->spectrum("irradiance", Extrapolate::Zero);
  s.irradiance *= t->real("scale", 1.0, 0.0, 1e6);
}

// model = "none" or a registered sky model, which reads its own parameters; spectrum, scale and
// ground_albedo apply to every model.
void parse_sky(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("sky");
  SkyDesc& s = b.scene().sky;
  const std::string model = t->string("model", "cie");
  if (model == "none") {
    s.enabled = false;
  } else {
    std::optional<SkyModel> m = create_registered<SkyModel>(model, *t);
    if (!m) t->fail("model", fmt::format("sky model must be {} or \"none\"", registered_names<SkyModel>()));
    s.model = *m;
    s.spectrum = std::visit([](const auto& sky) { return sky.default_spectrum(); }, s.model);
  }
  if (t->has("spectrum")) s.spectrum = t->spectrum("spectrum", Extrapolate::Zero);
  s.spectrum *= t->real("scale", 1.0, 0.0, 1e6);
  s.ground_albedo = t->real("ground_albedo", 0.0, 0.0, 1.0);
  if (s.ground_albedo > 0 && !(s.enabled && upper_hemisphere_only(s.model)))
    t->fail("ground_albedo", "ground_albedo needs model = \"cie\" or \"preetham\"");
  t->check_unused();
}

// An optional participating medium below `top`. Its extinction at 550 nm is given directly or as
// the meteorological visibility V (Koschmieder: σ = 3.912/V).
void parse_haze(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("haze");
  HazeDesc& h = b.scene().haze;
  h.enabled = t->boolean("enabled", true);
  const std::string profile = t->string("profile", "homogeneous");
  if (profile == "homogeneous")
    h.profile = HazeProfile::Homogeneous;
  else if (profile == "exponential")
    h.profile = HazeProfile::Exponential;
  else
    t->fail("profile", "haze profile must be \"homogeneous\" or \"exponential\"");
  if (t->has("extinction") == t->has("visibility"))
    t->fail("[haze] needs exactly one of extinction (1/m at 550 nm) or visibility (m)");
  h.extinction_550 = t->has("extinction") ? t->real("extinction", 0.0, 0.0, 100.0)
                                          : static_cast<float>(3.912 / t->real("visibility", 1.0, 1.0, 1e7));
  h.angstrom = t->real("angstrom", h.angstrom, 0.0, 4.0);
  h.albedo = t->real("albedo", h.albedo, 0.0, 1.0);
  h.g = t->real("g", h.g, -0.99, 0.99);
  h.base_height = t->real("base_height", h.base_height, -1e5, 1e5);
  h.scale_height = t->real("scale_height", h.scale_height, 1.0, 1e5);
  const double top_default = h.profile == HazeProfile::Homogeneous ? 1000.0 : 1e30;
  const float top = t->real("top", top_default, -1e5, 1e30);
  h.top = top >= 1e30f ? std::numeric_limits<float>::infinity() : top;
  if (h.profile == HazeProfile::Homogeneous && !std::isfinite(h.top))
    t->fail("top", "a homogeneous haze needs a finite top (m)");
  t->check_unused();
}

}  // namespace sylva
