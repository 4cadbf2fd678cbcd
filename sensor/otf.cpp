#include "sensor/otf.h"

#include "core/band.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sylva {

namespace {

constexpr double kPiOtf = std::numbers::pi;

double sinc(double x) { return x == 0.0 ? 1.0 : std::sin(kPiOtf * x) / (kPiOtf * x); }

// The clear circular aperture's OTF at ν (0 beyond 1).
double clear_aperture(double nu) {
  if (nu >= 1.0) return 0.0;
  return (2.0 / kPiOtf) * (std::acos(nu) - nu * std::sqrt(1.0 - nu * nu));
}

// The radial table at rho cycles/mm (linear between rows, the end rows held outside).
double table_otf(const OpticsParams& o, double rho) {
  const std::vector<double>& f = o.otf_cyc_per_mm;
  if (rho <= f.front()) return o.otf_value.front();
  if (rho >= f.back()) return o.otf_value.back();
  const size_t i = static_cast<size_t>(std::upper_bound(f.begin(), f.end(), rho) - f.begin());
  const double t = (rho - f[i - 1]) / (f[i] - f[i - 1]);
  return o.otf_value[i - 1] + t * (o.otf_value[i] - o.otf_value[i - 1]);
}

}  // namespace

SensorChannel describe_channel(const std::string& name, const std::string& band, const DenseSpectrum& weight) {
  const ChannelSummary summary = summarise_channel(weight);
  SensorChannel c;
  c.name = name;
  c.band = band;
  c.centre_nm = summary.centre_nm;
  c.equivalent_width_nm = summary.equivalent_width_nm;
  // 16 bins of equal width over the span where the response is positive; each bin's mass at its
  // response-weighted mean wavelength.
  double lo = 0, hi = 0;
  bool any = false;
  for (int i = 0; i < kLambdaSamples; ++i) {
    const double l = kLambdaMin + i;
    if (weight[i] > 0) {
      if (!any) lo = l;
      hi = l + 1;
      any = true;
    }
  }
  if (!any) return monochromatic_channel(name, c.centre_nm, c.equivalent_width_nm);
  constexpr int kBins = 16;
  std::vector<double> mass(kBins, 0.0), moment(kBins, 0.0);
  for (int i = 0; i < kLambdaSamples; ++i) {
    const double l = kLambdaMin + i + 0.5, w = std::max(0.0f, weight[i]);
    if (w <= 0) continue;
    const int b = std::min(kBins - 1, static_cast<int>((l - lo) / (hi - lo) * kBins));
    mass[static_cast<size_t>(b)] += w;
    moment[static_cast<size_t>(b)] += w * l;
  }
  double total = 0;
  for (double m : mass) total += m;
  for (int b = 0; b < kBins; ++b) {
    if (mass[static_cast<size_t>(b)] <= 0) continue;
    c.lambda_nm.push_back(moment[static_cast<size_t>(b)] / mass[static_cast<size_t>(b)]);
    c.weight.push_back(mass[static_cast<size_t>(b)] / total);
  }
  return c;
}

SensorChannel monochromatic_channel(const std::string& name, double lambda_nm, double equivalent_width_nm) {
  SensorChannel c;
  c.name = name;
  c.band = name;
  c.centre_nm = lambda_nm;
  c.equivalent_width_nm = equivalent_width_nm;
  c.lambda_nm = {lambda_nm};
  c.weight = {1.0};
  return c;
}

double obscured_aperture_otf(double nu, double eta) {
  nu = std::abs(nu);
  if (eta <= 0.0) return clear_aperture(nu);
  if (nu >= 1.0) return 0.0;
  const double a = clear_aperture(nu);
  const double b = nu < eta ? eta * eta * clear_aperture(nu / eta) : 0.0;
  double c = 0.0;  // the cross term: -2η² inside (1 - η)/2, 0 beyond (1 + η)/2
  if (nu <= (1.0 - eta) / 2.0) {
    c = -2.0 * eta * eta;
  } else if (nu < (1.0 + eta) / 2.0) {
    const double phi = std::acos(std::clamp((1.0 + eta * eta - 4.0 * nu * nu) / (2.0 * eta), -1.0, 1.0));
    c = (2.0 * eta / kPiOtf) * std::sin(phi) + ((1.0 + eta * eta) / kPiOtf) * phi - 2.0 * eta * eta -
        (2.0 * (1.0 - eta * eta) / kPiOtf) * std::atan((1.0 + eta) / (1.0 - eta) * std::tan(phi / 2.0));
  }
  return (a + b + c) / (1.0 - eta * eta);
}

double optics_otf(const OpticsParams& o, double pitch_um, const SensorChannel& channel, double u, double v) {
  const double rho2 = u * u + v * v, rho = std::sqrt(rho2);
  double diffraction = 0;
  for (size_t i = 0; i < channel.lambda_nm.size(); ++i) {
    const double cutoff = pitch_um * 1e3 / (channel.lambda_nm[i] * o.f_number);  // cycles per pitch
    diffraction += channel.weight[i] * obscured_aperture_otf(rho / cutoff, o.obscuration);
  }
  double h = diffraction;
  if (o.defocus_px > 0) h *= std::exp(-kPiOtf * kPiOtf / 4.0 * o.defocus_px * o.defocus_px * rho2);
  if (o.jitter_rms_px > 0) h *= std::exp(-2.0 * kPiOtf * kPiOtf * o.jitter_rms_px * o.jitter_rms_px * rho2);
  if (o.smear_px > 0) h *= sinc(o.smear_px * u);
  if (!o.otf_cyc_per_mm.empty()) h *= table_otf(o, rho / (pitch_um * 1e-3));
  return h;
}

double footprint_mtf(double u, double v) { return sinc(u) * sinc(v); }

double system_otf(const OpticsParams& optics, double pitch_um, const SensorChannel& channel, double u, double v) {
  return optics_otf(optics, pitch_um, channel, u, v) * footprint_mtf(u, v);
}

}  // namespace sylva
