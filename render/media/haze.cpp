#include "render/media/haze.h"

#include "core/error.h"
#include "core/fast_math.h"

#include <cmath>

namespace sylva {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

float henyey_greenstein(float cos_theta, float g) {
  const float denom = 1.0f + g * g - 2.0f * g * cos_theta;
  return (1.0f - g * g) / (4.0f * kPi * denom * std::sqrt(denom));
}

Vec3 sample_henyey_greenstein(const Vec3& a, float g, Vec2 u) {
  // Inverse of the cumulative distribution in μ = cos θ (e.g. Pharr et al., PBR 3rd ed. §15.2.3).
  float mu;
  if (std::abs(g) < 1e-3f) {
    mu = 1.0f - 2.0f * u.x;
  } else {
    const float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u.x);
    mu = (1.0f + g * g - s * s) / (2.0f * g);
  }
  mu = std::clamp(mu, -1.0f, 1.0f);
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - mu * mu));
  return Frame::from_z(a).to_world(spherical_direction_fast(sin_theta, mu, kTwoPi * u.y));
}

Haze::Haze(const HazeDesc& desc) : desc_(desc) {
  if (!desc.enabled) return;
  if (!(desc.extinction_550 >= 0.0f && std::isfinite(desc.extinction_550)))
    throw Error("haze: extinction must be finite and >= 0");
  if (!(desc.albedo >= 0.0f && desc.albedo <= 1.0f)) throw Error("haze: albedo must lie in [0, 1]");
  if (!(desc.g > -1.0f && desc.g < 1.0f)) throw Error("haze: g must lie in (-1, 1)");
  if (!(desc.scale_height > 0.0f)) throw Error("haze: scale height must be > 0");
  if (desc.profile == HazeProfile::Homogeneous && !std::isfinite(desc.top))
    throw Error("haze: a homogeneous haze needs a finite top");
}

SampledSpectrum Haze::spectral_factor(const SampledWavelengths& wl) const {
  SampledSpectrum k;
  for (int i = 0; i < kLambdaCount; ++i) k[i] = std::pow(wl.lambda_nm[i] / 550.0f, -desc_.angstrom);
  return k;
}

double Haze::extinction_550(double z) const {
  if (z >= desc_.top) return 0.0;
  if (desc_.profile == HazeProfile::Homogeneous) return desc_.extinction_550;
  return desc_.extinction_550 * std::exp(-(z - desc_.base_height) / desc_.scale_height);
}

bool Haze::segment(const Vec3& o, const Vec3& d, double& s_in, double& s_out) const {
  s_in = 0.0;
  s_out = kInf;
  if (!std::isfinite(desc_.top)) return true;
  const double dz = d.z, height = desc_.top - static_cast<double>(o.z);
  if (height > 0) {
    if (dz > 0) s_out = height / dz;
    return true;
  }
  if (dz >= 0) return false;
  s_in = height / dz;
  return true;
}

// Along the ray σ₀(s) = σ₀(s_a)·exp(−b(s − s_a)) with b = d_z/H (b = 0 when homogeneous), so
// τ₀ over [s_a, s_b] = σ₀(s_a)·(1 − exp(−b(s_b − s_a)))/b, and its inverse is a logarithm.
double Haze::optical_depth(const Vec3& o, const Vec3& d, double s0, double s1) const {
  double s_in, s_out;
  if (!segment(o, d, s_in, s_out)) return 0.0;
  const double a = std::max(s0, s_in), e = std::min(s1, s_out);
  if (!(e > a)) return 0.0;
  const double sigma_a =
      desc_.profile == HazeProfile::Homogeneous
          ? desc_.extinction_550
          : desc_.extinction_550 * std::exp(-(o.z + a * d.z - desc_.base_height) / desc_.scale_height);
  const double b = desc_.profile == HazeProfile::Homogeneous ? 0.0 : d.z / desc_.scale_height;
  if (sigma_a == 0.0) return 0.0;
  if (std::abs(b) < 1e-12) return sigma_a * (e - a);
  if (!std::isfinite(e)) return b > 0 ? sigma_a / b : kInf;
  return sigma_a * -std::expm1(-b * (e - a)) / b;
}

double Haze::distance_at_depth(const Vec3& o, const Vec3& d, double s0, double tau) const {
  double s_in, s_out;
  if (!segment(o, d, s_in, s_out)) return kInf;
  const double a = std::max(s0, s_in);
  if (!(s_out > a)) return kInf;
  if (tau >= optical_depth(o, d, a, s_out)) return kInf;
  const double sigma_a =
      desc_.profile == HazeProfile::Homogeneous
          ? desc_.extinction_550
          : desc_.extinction_550 * std::exp(-(o.z + a * d.z - desc_.base_height) / desc_.scale_height);
  const double b = desc_.profile == HazeProfile::Homogeneous ? 0.0 : d.z / desc_.scale_height;
  if (std::abs(b) < 1e-12) return a + tau / sigma_a;
  return a - std::log1p(-tau * b / sigma_a) / b;
}

SampledSpectrum Haze::transmittance(const Vec3& o, const Vec3& d, float t, const SampledWavelengths& wl) const {
  const double tau = optical_depth(o, d, 0.0, t);
  const SampledSpectrum k = spectral_factor(wl);
  SampledSpectrum out;
  for (int i = 0; i < kLambdaCount; ++i) out[i] = static_cast<float>(std::exp(-static_cast<double>(k[i]) * tau));
  return out;
}

float Haze::sample_scattering(const Vec3& o, const Vec3& d, float t_max, const SampledWavelengths& wl, float u,
                              SampledSpectrum& beta, SampledSpectrum& ratio) const {
  const SampledSpectrum k = spectral_factor(wl);
  // The hero wavelength's free flight, by inverting τ₀ exactly.
  const double tau = -std::log(1.0 - static_cast<double>(u)) / k[wl.hero];
  const double s = distance_at_depth(o, d, 0.0, tau);
  const bool collided = s < t_max;
  const double tau0 = collided ? tau : optical_depth(o, d, 0.0, t_max);
  if (!std::isfinite(tau0)) {
    beta = SampledSpectrum(0.0f);
    return std::numeric_limits<float>::infinity();
  }
  // Each wavelength's density of this outcome up to a common factor: k·e (collision) or e (passage),
  // e = exp(−(k − k_min)·τ₀) ≤ 1. The balance heuristic over the carried wavelengths divides the
  // contribution f/p_hero by the mean of r·p/p_hero; the common factor and p_hero cancel.
  const float k_min = min_component(k);
  SampledSpectrum p;
  for (int i = 0; i < kLambdaCount; ++i) {
    const float e = static_cast<float>(std::exp(-static_cast<double>(k[i] - k_min) * tau0));
    p[i] = collided ? k[i] * e : e;
  }
  const float m = average(ratio * p);
  if (!(m > 0.0f)) {
    beta = SampledSpectrum(0.0f);
    return std::numeric_limits<float>::infinity();
  }
  beta *= (collided ? desc_.albedo : 1.0f) * p / m;
  ratio *= p / m;
  return collided ? static_cast<float>(s) : std::numeric_limits<float>::infinity();
}

}  // namespace sylva
