#include "render/lights/preetham_sky.h"

#include "core/data_path.h"
#include "core/error.h"

#include <cmath>

namespace sylva {

namespace {

struct Perez {
  float a, b, c, d, e;
  // Perez et al. 1993: F(θ, γ) = (1 + A e^{B/cos θ})(1 + C e^{Dγ} + E cos²γ).
  float operator()(float cos_theta, float gamma) const {
    const float cos_gamma = std::cos(gamma);
    return (1.0f + a * std::exp(b / std::max(cos_theta, 1e-3f))) *
           (1.0f + c * std::exp(d * gamma) + e * cos_gamma * cos_gamma);
  }
};

// Preetham et al. 1999, Appendix A.2: the distribution coefficients as linear functions of T.
Perez perez_Y(float t) {
  return {0.1787f * t - 1.4630f, -0.3554f * t + 0.4275f, -0.0227f * t + 5.3251f, 0.1206f * t - 2.5771f,
          -0.0670f * t + 0.3703f};
}
Perez perez_x(float t) {
  return {-0.0193f * t - 0.2592f, -0.0665f * t + 0.0008f, -0.0004f * t + 0.2125f, -0.0641f * t - 0.8989f,
          -0.0033f * t + 0.0452f};
}
Perez perez_y(float t) {
  return {-0.0167f * t - 0.2608f, -0.0950f * t + 0.0092f, -0.0079f * t + 0.2102f, -0.0441f * t - 1.6537f,
          -0.0109f * t + 0.0529f};
}

// Zenith chromaticity (Appendix A.2), θs the sun's zenith angle in radians.
float zenith_chromaticity(float t, float ts, const float (&m)[3][4]) {
  const float ts2 = ts * ts, ts3 = ts2 * ts;
  float out = 0.0f, tp = 1.0f;
  for (int row = 2; row >= 0; --row) {
    out += tp * (m[row][0] * ts3 + m[row][1] * ts2 + m[row][2] * ts + m[row][3]);
    tp *= t;
  }
  return out;
}

constexpr float kZenithX[3][4] = {{0.00166f, -0.00375f, 0.00209f, 0.0f},
                                  {-0.02903f, 0.06377f, -0.03202f, 0.00394f},
                                  {0.11693f, -0.21196f, 0.06052f, 0.25886f}};
constexpr float kZenithY[3][4] = {{0.00275f, -0.00610f, 0.00317f, 0.0f},
                                  {-0.04214f, 0.08970f, -0.04153f, 0.00516f},
                                  {0.15346f, -0.26756f, 0.06670f, 0.26688f}};

struct Daylight {
  std::array<DenseSpectrum, 3> visible;  // S0, S1, S2 as tabulated (300–830 nm)
  std::array<double, 3> luminance;       // ∫ S_i ȳ dλ
};

const Daylight& daylight() {
  static const Daylight d = [] {
    Daylight out;
    const char* names[3] = {"S0", "S1", "S2"};
    for (int i = 0; i < 3; ++i) {
      out.visible[i] = load_spectrum(data_file("cie_daylight_components_10nm.csv"), names[i], Extrapolate::Clamp);
      out.luminance[i] = out.visible[i].integral_product(cie_y());
    }
    return out;
  }();
  return d;
}

}  // namespace

Vec3 preetham_xyY(float turbidity, const Vec3& dir, const Vec3& sun_dir) {
  if (dir.z <= 0) return Vec3(0.0f);
  const float t = turbidity;
  const float theta_s = safe_acos(sun_dir.z);
  const float gamma = safe_acos(glm::dot(dir, sun_dir));
  const float cos_theta = dir.z;
  const Perez fY = perez_Y(t), fx = perez_x(t), fy = perez_y(t);
  // The sun's zenith angle is limited to the horizon (the fit's range); Preetham §A.2.
  const float ts = std::min(theta_s, 0.5f * kPi);
  const float x = zenith_chromaticity(t, ts, kZenithX) * fx(cos_theta, gamma) / fx(1.0f, ts);
  const float y = zenith_chromaticity(t, ts, kZenithY) * fy(cos_theta, gamma) / fy(1.0f, ts);
  const float Y = std::max(0.0f, fY(cos_theta, gamma) / fY(1.0f, ts));
  return Vec3(x, y, Y);
}

PreethamSky PreethamSky::create(const Params& params) {
  PreethamSky sky;
  sky.turbidity = params.real("turbidity", sky.turbidity, 1.7, 10.0);
  sky.own_spectrum = !params.has("spectrum");
  return sky;
}

float PreethamSky::relative_radiance(const Vec3& dir, const Vec3& sun_dir) const {
  return preetham_xyY(turbidity, dir, sun_dir).z;
}

Vec3 PreethamSky::basis_weights(const Vec3& dir, const Vec3& sun_dir) const {
  const Vec3 xyY = preetham_xyY(turbidity, dir, sun_dir);
  if (xyY.z <= 0) return Vec3(0.0f);
  // CIE 15:2004 §3.1: the daylight of chromaticity (x, y).
  const float x = xyY.x, y = xyY.y;
  const float m = 0.0241f + 0.2562f * x - 0.7341f * y;
  const float m1 = (-1.3515f - 1.7703f * x + 5.9114f * y) / m;
  const float m2 = (0.0300f - 31.4424f * x + 30.0717f * y) / m;
  const std::array<double, 3>& l = daylight().luminance;
  const double luminance = l[0] + m1 * l[1] + m2 * l[2];
  if (!(luminance > 0)) return Vec3(0.0f);
  const float k = static_cast<float>(xyY.z / luminance);
  return k * Vec3(1.0f, m1, m2);
}

std::array<DenseSpectrum, 3> PreethamSky::basis() const {
  std::array<DenseSpectrum, 3> out = daylight().visible;
  // Beyond 780 nm: the single-scattering law f(λ) of the header, anchored at 780 nm.
  const DenseSpectrum& beam = astm_g173_direct();
  auto f = [&](float lambda, float beam_value) {
    const float r = lambda / 550.0f;
    return beam_value * (std::pow(r, -4.08f) + (turbidity - 1.0f) * std::pow(r, -1.3f));
  };
  constexpr int kAnchor = 780 - static_cast<int>(kLambdaMin);
  double beam_anchor = 0;  // the beam averaged over 776–784 nm, clear of the oxygen A band's edge
  for (int i = kAnchor - 4; i <= kAnchor + 4; ++i) beam_anchor += beam[i] / 9.0;
  const float f_anchor = f(780.0f, static_cast<float>(beam_anchor));
  for (DenseSpectrum& s : out) {
    const float anchor = s[kAnchor];
    for (int i = kAnchor + 1; i < kLambdaSamples; ++i)
      s[i] = anchor * f(DenseSpectrum::grid_lambda(i), beam[i]) / f_anchor;
  }
  return out;
}

}  // namespace sylva
