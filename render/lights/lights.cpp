#include "render/lights/lights.h"

#include "core/data_path.h"
#include "core/error.h"
#include "core/table.h"

#include <array>
#include <cmath>

namespace sylva {

namespace {

// The sky's normalisation integrals: the midpoint rule on a (φ, θ) grid this fine.
constexpr int kNormalisationPhiBins = 256;
constexpr int kNormalisationThetaBins = 128;
// The sky's sampling table over (φ, cos θ): 8 192 cells of 2.8° × 1/64 in cos θ (1/32 with a
// ground), 130 KB with its guides and densities. The table twice as fine each way (520 KB, larger
// than a core's second-level cache here) was 3–5 % slower per ray, each sky sample and MIS density
// reading it from farther out (bench/README.md, "The sky's table at half the resolution"); the sky's
// shape is smooth at this scale, and the sun's cells are emptied either way.
constexpr int kSkyPhiBins = 128;
constexpr int kSkyThetaBins = 64;

}  // namespace

Vec3 sun_direction(float azimuth_deg, float elevation_deg) {
  const float az = radians(azimuth_deg), el = radians(elevation_deg);
  return glm::normalize(Vec3(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el)));
}

Environment::Environment(const SunDesc& sun, const SkyDesc& sky) : sun_(sun), sky_(sky) {
  const Vec3 sun_dir = sun_direction(sun.azimuth_deg, sun.elevation_deg);
  sky_.sun_direction = sun_dir;
  std::visit(
      [&](auto& m) {
        if constexpr (requires { m.prepare(sun_dir); }) m.prepare(sun_dir);
      },
      sky_.model);
  if (const CieSky* cie = std::get_if<CieSky>(&sky.model); cie && (cie->type < 1 || cie->type > 15))
    throw Error("sky: CIE standard sky type must be 1..15");
  if (!(sky.ground_albedo >= 0.0f && sky.ground_albedo <= 1.0f)) throw Error("sky: ground albedo must lie in [0, 1]");
  has_ground_ = sky.enabled && upper_hemisphere_only(sky.model) && sky.ground_albedo > 0.0f;
  if (sky.ground_albedo > 0.0f && !has_ground_) throw Error("sky: a ground albedo needs a sky above the horizon only");

  // Sun: a uniform disc whose radiance gives the irradiance at normal incidence, E = π L sin²α.
  float sun_power = 0;
  if (sun.enabled) {
    if (!(sun.angular_radius_deg > 0 && sun.angular_radius_deg < 10))
      throw Error("sun: angular radius must be in (0, 10) degrees");
    sun_frame_ = Frame::from_z(sun_dir);
    sun_one_minus_cos_ = one_minus_cos(radians(sun.angular_radius_deg));
    sun_radiance_ = sun.irradiance;
    sun_radiance_ *= 1.0f / (kPi * sqr(std::sin(radians(sun.angular_radius_deg))));
    sun_power = static_cast<float>(sun.irradiance.integral());
  }

  // Sky: its normalisation from the directional shape g(ω), and its sampling table (sky_table).
  float sky_power = 0;
  if (sky.enabled) {
    spectral_sky_ = std::visit([](const auto& m) { return SpectralSkyModel<std::decay_t<decltype(m)>>; }, sky.model);
    // The normalisation integrals, by the midpoint rule on a (φ, θ) grid over the sky's extent.
    double horizontal = 0;                            // ∫ g cos θ dω over the upper hemisphere
    std::vector<std::pair<Vec3, float>> basis_cells;  // spectral skies: (w_i(ω), cos θ dω) per upper cell
    const float theta_max = !upper_hemisphere_only(sky.model) || has_ground_ ? kPi : 0.5f * kPi;
    const float dphi = kTwoPi / kNormalisationPhiBins, dtheta = theta_max / kNormalisationThetaBins;
    for (int j = 0; j < kNormalisationThetaBins; ++j) {
      const float theta = (j + 0.5f) * dtheta;
      for (int i = 0; i < kNormalisationPhiBins; ++i) {
        const Vec3 d = spherical_direction(std::sin(theta), std::cos(theta), (i + 0.5f) * dphi);
        const float g = sky_shape(d);
        if (d.z > 0) horizontal += g * d.z * std::sin(theta) * dphi * dtheta;
        if (spectral_sky_ && d.z > 0) {
          basis_cells.emplace_back(sky_basis_weights(d), d.z * std::sin(theta) * dphi * dtheta);
        }
      }
    }
    sky_horizontal_ = horizontal;
    if (spectral_sky_) {
      fit_spectral_sky(sky, basis_cells);
      // Radiance per unit relative luminance, for the mixture's sky probability and the ground.
      const DenseSpectrum e = horizontal_irradiance_of_sky();
      sky_radiance_ = e;
      sky_radiance_ *= static_cast<float>(1.0 / horizontal);
      sky_power = static_cast<float>(e.integral());
    } else if (!normalised_to_horizontal(sky.model)) {
      sky_radiance_ = sky.spectrum;
      sky_power = static_cast<float>(sky.spectrum.integral() * kPi);
    } else {
      sky_radiance_ = sky.spectrum;
      sky_radiance_ *= static_cast<float>(1.0 / horizontal);
      sky_power = static_cast<float>(sky.spectrum.integral());
    }
    float ground_weight = 0;  // the ground's sampling weight per steradian, in the sky's shape units
    if (has_ground_) {
      // L_ground = a/π · (E_sun sin(elevation) + E_sky,horizontal), uniform over the lower hemisphere;
      // its table cells are weighted by its power relative to the sky's shape units.
      ground_radiance_ = spectral_sky_ ? horizontal_irradiance_of_sky() : sky.spectrum;
      if (sun.enabled)
        for (int i = 0; i < kLambdaSamples; ++i) ground_radiance_[i] += sun.irradiance[i] * std::max(0.0f, sun_dir.z);
      ground_radiance_ *= sky.ground_albedo * kInvPi;
      const double sky_scale = sky_radiance_.integral();
      ground_weight = sky_scale > 0 ? static_cast<float>(ground_radiance_.integral() / sky_scale) : 1.0f;
      sky_power += static_cast<float>(ground_radiance_.integral() * kPi);
    }
    sky_z_min_ = theta_max == kPi ? -1.0f : 0.0f;
    sky_distribution_ = Distribution2D(sky_table(ground_weight), kSkyPhiBins, kSkyThetaBins);
  }
  const float total = sun_power * std::max(0.0f, sun_dir.z) + sky_power;
  if (sun_power > 0 && sky_power > 0 && total > 0) {
    p_sun_ = std::clamp(sun_power * std::max(0.0f, sun_dir.z) / total, 0.2f, 0.8f);
    p_sky_ = 1.0f - p_sun_;
  } else {
    p_sun_ = sun_power > 0 ? 1.0f : 0.0f;
    p_sky_ = sky_power > 0 ? 1.0f : 0.0f;
  }
}

// E_model(λ) = ∫ max(0, Σ_i w_i(ω) S_i(λ)) cos θ dω on the table (the daylight formula dips below 0
// in the UV for chromaticities off the daylight locus, and the radiance is clamped there); scaled to
// the stated horizontal irradiance per wavelength, or in total when the model keeps its own spectrum.
void Environment::fit_spectral_sky(const SkyDesc& sky, const std::vector<std::pair<Vec3, float>>& basis_cells) {
  std::visit(
      [&](const auto& m) {
        if constexpr (SpectralSkyModel<std::decay_t<decltype(m)>>) {
          sky_basis_ = m.basis();
          // Beyond 780 nm the basis is one positive factor times its 780 nm values, where every
          // daylight spectrum is positive: there the integral is linear in the weights.
          constexpr int kLinearFrom = 780 - static_cast<int>(kLambdaMin);
          std::array<double, 3> linear{};
          for (const auto& [c, dw] : basis_cells)
            for (int k = 0; k < 3; ++k) linear[k] += static_cast<double>(c[k]) * dw;
          DenseSpectrum model;
          for (int i = 0; i < kLambdaSamples; ++i) {
            double e = 0;
            if (i <= kLinearFrom) {
              for (const auto& [c, dw] : basis_cells)
                e += std::max(0.0f, c.x * sky_basis_[0][i] + c.y * sky_basis_[1][i] + c.z * sky_basis_[2][i]) * dw;
            } else {
              for (int k = 0; k < 3; ++k) e += linear[k] * sky_basis_[k][i];
            }
            model[i] = static_cast<float>(e);
          }
          DenseSpectrum scale;
          if (m.own_spectrum) {
            const double total = model.integral();
            scale = DenseSpectrum::constant(total > 0 ? static_cast<float>(sky.spectrum.integral() / total) : 0.0f);
          } else {
            for (int i = 0; i < kLambdaSamples; ++i) scale[i] = model[i] > 0 ? sky.spectrum[i] / model[i] : 0.0f;
          }
          for (DenseSpectrum& b : sky_basis_) b = b * scale;
          sky_horizontal_spectrum_ = model * scale;
        }
      },
      sky.model);
}

std::vector<float> Environment::sky_table(float ground_weight) const {
  std::vector<float> w(static_cast<size_t>(kSkyPhiBins) * kSkyThetaBins);
  const float dphi = kTwoPi / kSkyPhiBins, dz = (1.0f - sky_z_min_) / kSkyThetaBins;
  for (int j = 0; j < kSkyThetaBins; ++j) {
    const float z = 1.0f - (static_cast<float>(j) + 0.5f) * dz;
    for (int i = 0; i < kSkyPhiBins; ++i)
      w[static_cast<size_t>(j) * kSkyPhiBins + i] =
          has_ground_ && z < 0 ? ground_weight
                               : sky_shape(spherical_direction(safe_sqrt(1.0f - z * z), z, (i + 0.5f) * dphi));
  }
  if (!sun_.enabled) return w;
  // Empty the cells the solar disc may reach: every direction within a of the sun's axis lies in
  // θ_s ± a and, on those rows, within φ_s ± h with sin h = sin a / min sin θ (sin is concave, so
  // its least value over the rows is at an end). a exceeds the disc's radius by 1 % + 10⁻⁴ rad, far
  // above the rounding of a sampled direction (10⁻⁷) and in_sun's margin (10⁻⁵ of 1 − cos α).
  const float a = 1.01f * radians(sun_.angular_radius_deg) + 1e-4f;
  const float theta_s = safe_acos(sun_frame_.z.z);
  const float phi_s = spherical_phi(sun_frame_.z);
  const float z_hi = std::cos(std::max(0.0f, theta_s - a)), z_lo = std::cos(std::min(kPi, theta_s + a));
  const float min_sin = std::min(std::sin(std::max(0.0f, theta_s - a)), std::sin(std::min(kPi, theta_s + a)));
  const float h = min_sin > std::sin(a) ? std::asin(std::sin(a) / min_sin) : kPi;
  for (int j = 0; j < kSkyThetaBins; ++j) {
    const float row_hi = 1.0f - static_cast<float>(j) * dz, row_lo = 1.0f - static_cast<float>(j + 1) * dz;
    if (row_lo > z_hi || row_hi < z_lo) continue;
    for (int i = 0; i < kSkyPhiBins; ++i) {
      const float d = std::abs(std::remainder((static_cast<float>(i) + 0.5f) * dphi - phi_s, kTwoPi));
      if (d <= h + 0.5f * dphi) w[static_cast<size_t>(j) * kSkyPhiBins + i] = 0.0f;
    }
  }
  return w;
}

DenseSpectrum Environment::horizontal_irradiance_of_sky() const {
  DenseSpectrum e;
  if (!sky_.enabled) return e;
  if (spectral_sky_) return sky_horizontal_spectrum_;
  e = sky_radiance_;
  e *= static_cast<float>(sky_horizontal_);
  return e;
}

DenseSpectrum Environment::horizontal_irradiance() const {
  DenseSpectrum e = horizontal_irradiance_of_sky();
  if (sun_.enabled) {
    const float cos_sun = std::max(0.0f, sun_frame_.z.z);
    for (int i = 0; i < kLambdaSamples; ++i) e[i] += sun_.irradiance[i] * cos_sun;
  }
  return e;
}

float Environment::sky_shape(const Vec3& dir) const {
  return std::visit([&](const auto& m) { return m.relative_radiance(dir, sky_.sun_direction); }, sky_.model);
}

Vec3 Environment::sky_basis_weights(const Vec3& dir) const {
  return std::visit(
      [&](const auto& m) {
        if constexpr (SpectralSkyModel<std::decay_t<decltype(m)>>)
          return m.basis_weights(dir, sky_.sun_direction);
        else
          return Vec3(0.0f);
      },
      sky_.model);
}

SampledSpectrum Environment::eval_sky(const Vec3& dir, const SampledWavelengths& wl) const {
  if (!sky_.enabled) return SampledSpectrum(0.0f);
  if (has_ground_ && dir.z < 0) return ground_radiance_.eval(wl);
  SampledSpectrum l(0.0f);
  if (spectral_sky_) {
    const Vec3 c = sky_basis_weights(dir);
    if (c == Vec3(0.0f)) return l;
    l = clamp_zero(c.x * sky_basis_[0].eval(wl) + c.y * sky_basis_[1].eval(wl) + c.z * sky_basis_[2].eval(wl));
  } else if (const float g = sky_shape(dir); g > 0) {
    l = g * sky_radiance_.eval(wl);
  }
  if (horizon_gain_ != 1.0f && dir.z >= 0 && dir.z < horizon_z_) l *= horizon_gain_;
  return l;
}

void Environment::inject_horizon_fault(float gain, float elevation_deg) {
  horizon_gain_ = gain;
  horizon_z_ = std::sin(elevation_deg * kPi / 180.0f);
}

SampledSpectrum Environment::eval(const Vec3& dir, const SampledWavelengths& wl) const {
  if (sun_.enabled && in_sun(dir)) return sun_radiance_.eval(wl);
  return eval_sky(dir, wl);
}

float Environment::sky_pdf(const Vec3& dir) const {
  if (dir.z <= sky_z_min_) return 0.0f;
  const float p =
      sky_distribution_.pdf(Vec2(spherical_phi_fast(dir) * kInvTwoPi, (1.0f - dir.z) / (1.0f - sky_z_min_)));
  return p / (kTwoPi * (1.0f - sky_z_min_));
}

float Environment::pdf(const Vec3& dir) const {
  float p = 0;
  if (p_sun_ > 0 && in_sun(dir)) p += p_sun_ * uniform_cone_pdf(sun_one_minus_cos_);
  if (p_sky_ > 0) p += p_sky_ * sky_pdf(dir);
  return p;
}

LightSample Environment::sample(Vec2 u, float u_select, const SampledWavelengths& wl) const {
  LightSample s;
  if (u_select < p_sun_) {
    s.wi = sun_frame_.to_world(sample_uniform_cone(u, sun_one_minus_cos_));
    // The sky's table is empty wherever the disc reaches (sky_table): the mixture's density here
    // is the sun's alone, pdf(s.wi) without its sky lookup.
    s.pdf = p_sun_ * uniform_cone_pdf(sun_one_minus_cos_);
    s.radiance = sun_radiance_.eval(wl);
    return s;
  }
  if (p_sky_ == 0) return s;
  const Vec2 uv = sky_distribution_.sample(u, nullptr);
  const float z = 1.0f - uv.y * (1.0f - sky_z_min_);
  s.wi = spherical_direction_fast(safe_sqrt(1.0f - z * z), z, uv.x * kTwoPi);
  // The density of the direction as pdf() finds it (not the sampled cell's: rounding can put a
  // direction on a cell's edge in the neighbouring cell, about 4 in 10⁵), so the two always agree.
  s.pdf = pdf(s.wi);
  // The sky's radiance: the cells the solar disc may reach are empty (sky_table).
  s.radiance = eval_sky(s.wi, wl);
  return s;
}

}  // namespace sylva
