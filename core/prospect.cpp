#include "core/prospect.h"

#include "core/data_path.h"
#include "core/error.h"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

namespace sylva {

namespace {

constexpr int kFirstLambdaNm = 400;
constexpr int kLastLambdaNm = 2500;
constexpr size_t kSamples = kLastLambdaNm - kFirstLambdaNm + 1;

// Columns of prospect_d_spectra.txt after λ: n, k_Cab, k_Car, k_Anth, k_Brown, k_Cw, k_Cm.
struct ProspectDTable {
  std::vector<float> lambda_nm;
  std::vector<double> n, k_cab, k_car, k_ant, k_brown, k_cw, k_cm;
};

ProspectDTable load_prospect_d_table() {
  const std::filesystem::path file = data_file("prospect/prospect_d_spectra.txt");
  std::ifstream in(file);
  if (!in) throw Error("cannot open " + file.string());
  ProspectDTable t;
  std::array<std::vector<double>*, 7> cols{&t.n, &t.k_cab, &t.k_car, &t.k_ant, &t.k_brown, &t.k_cw, &t.k_cm};
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::array<double, 8> v{};
    const char* p = line.data() + first;
    const char* end = line.data() + line.size();
    for (size_t c = 0; c < v.size(); ++c) {
      while (p < end && (*p == ' ' || *p == '\t' || *p == ',')) ++p;
      const auto [next, ec] = std::from_chars(p, end, v[c]);
      if (ec != std::errc() || !std::isfinite(v[c]))
        throw ParseError(file, line_no, "expected 8 numbers (lambda n k_Cab k_Car k_Anth k_Brown k_Cw k_Cm)");
      p = next;
    }
    const int expected_nm = kFirstLambdaNm + static_cast<int>(t.lambda_nm.size());
    if (v[0] != expected_nm)
      throw ParseError(file, line_no, "expected wavelength " + std::to_string(expected_nm) + " nm");
    t.lambda_nm.push_back(static_cast<float>(v[0]));
    for (size_t c = 0; c < cols.size(); ++c) cols[c]->push_back(v[c + 1]);
  }
  if (t.lambda_nm.size() != kSamples)
    throw ParseError(file, line_no,
                     "expected rows for 400..2500 nm at 1 nm, found " + std::to_string(t.lambda_nm.size()));
  return t;
}

const ProspectDTable& prospect_d_table() {
  static const ProspectDTable table = load_prospect_d_table();
  return table;
}

}  // namespace

double exponential_integral_e1(double x) {
  if (!(x > 0)) return std::numeric_limits<double>::infinity();
  constexpr double kEulerGamma = 0.57721566490153286061;
  constexpr double kEps = 1e-16;
  if (x <= 1.0) {
    // Power series: E1(x) = -γ - ln x - Σ_{k≥1} (-x)^k / (k·k!).
    double sum = 0.0;
    double term = 1.0;  // (-x)^k / k!
    for (int k = 1; k < 100; ++k) {
      term *= -x / k;
      const double add = term / k;
      sum += add;
      if (std::abs(add) < kEps * std::abs(sum)) break;
    }
    return -kEulerGamma - std::log(x) - sum;
  }
  // Continued fraction (modified Lentz), e.g. Numerical Recipes §6.3 with n = 1.
  constexpr double kTiny = 1e-300;
  double b = x + 1.0;
  double c = 1.0 / kTiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -static_cast<double>(i) * i;
    b += 2.0;
    d = 1.0 / (an * d + b);
    c = b + an / c;
    const double del = c * d;
    h *= del;
    if (std::abs(del - 1.0) < kEps) break;
  }
  return h * std::exp(-x);
}

// Stern 1964; Allen 1973: transmissivity averaged over incidence angles in [0, alpha].
double prospect_tav(double alpha_deg, double n) {
  const double n2 = n * n;
  const double np = n2 + 1.0;
  const double nm = n2 - 1.0;
  const double a = (n + 1.0) * (n + 1.0) / 2.0;
  const double k = -(n2 - 1.0) * (n2 - 1.0) / 4.0;
  const double sa = std::sin(alpha_deg * (3.14159265358979323846 / 180.0));
  const double b2 = sa * sa - np / 2.0;
  const double b1 = alpha_deg == 90.0 ? 0.0 : std::sqrt(b2 * b2 + k);
  const double b = b1 - b2;
  const double b3 = b * b * b;
  const double a3 = a * a * a;
  const double ts = (k * k / (6.0 * b3) + k / b - b / 2.0) - (k * k / (6.0 * a3) + k / a - a / 2.0);
  const double tp1 = -2.0 * n2 * (b - a) / (np * np);
  const double tp2 = -2.0 * n2 * np * std::log(b / a) / (nm * nm);
  const double tp3 = n2 * (1.0 / b - 1.0 / a) / 2.0;
  const double tp4 = 16.0 * n2 * n2 * (n2 * n2 + 1.0) * std::log((2.0 * np * b - nm * nm) / (2.0 * np * a - nm * nm)) /
                     (np * np * np * nm * nm);
  const double tp5 =
      16.0 * n2 * n2 * n2 * (1.0 / (2.0 * np * b - nm * nm) - 1.0 / (2.0 * np * a - nm * nm)) / (np * np * np);
  const double tp = tp1 + tp2 + tp3 + tp4 + tp5;
  return (ts + tp) / (2.0 * sa * sa);
}

LeafOptics prospect_plate_model(std::span<const float> lambda_nm, std::span<const double> n,
                                std::span<const double> absorption, double N) {
  if (n.size() != lambda_nm.size() || absorption.size() != lambda_nm.size())
    throw Error("prospect_plate_model: refractive index, absorption and wavelengths differ in length");
  if (!(N >= 1.0) || !std::isfinite(N)) throw Error("PROSPECT: N must be a finite number ≥ 1");
  constexpr double kAlphaDeg = 40.0;
  LeafOptics out;
  out.lambda_nm.assign(lambda_nm.begin(), lambda_nm.end());
  out.reflectance.resize(lambda_nm.size());
  out.transmittance.resize(lambda_nm.size());
  for (size_t i = 0; i < lambda_nm.size(); ++i) {
    const double nr = n[i];
    const double kall = absorption[i];
    // Transmissivity of one plate's absorbing layer for isotropic light (Allen et al. 1969):
    // τ = (1 - K) e^{-K} + K² E1(K).
    const double tau = kall > 0 ? (1.0 - kall) * std::exp(-kall) + kall * kall * exponential_integral_e1(kall) : 1.0;

    // One plate: interface transmissivities for the 40° incidence cone and for isotropic light.
    const double talf = prospect_tav(kAlphaDeg, nr);
    const double ralf = 1.0 - talf;
    const double t12 = prospect_tav(90.0, nr);
    const double r12 = 1.0 - t12;
    const double t21 = t12 / (nr * nr);
    const double r21 = 1.0 - t21;
    const double denom1 = 1.0 - r21 * r21 * tau * tau;
    const double Ta = talf * tau * t21 / denom1;  // top surface
    const double Ra = ralf + r21 * tau * Ta;
    const double t = t12 * tau * t21 / denom1;  // interior plates
    const double r = r12 + r21 * tau * t;

    // N - 1 further plates, N real (Stokes 1862).
    double Rsub = 0.0;
    double Tsub = 0.0;
    if (r + t >= 1.0) {  // no absorption
      Tsub = t / (t + (1.0 - t) * (N - 1.0));
      Rsub = 1.0 - Tsub;
    } else {
      const double D = std::sqrt(std::max(0.0, (1 + r + t) * (1 + r - t) * (1 - r + t) * (1 - r - t)));
      const double rq = r * r;
      const double tq = t * t;
      const double a = (1.0 + rq - tq + D) / (2.0 * r);
      const double b = (1.0 - rq + tq + D) / (2.0 * t);
      const double bNm1 = std::pow(b, N - 1.0);
      const double bN2 = bNm1 * bNm1;
      const double a2 = a * a;
      const double denom = a2 * bN2 - 1.0;
      Rsub = a * (bN2 - 1.0) / denom;
      Tsub = bNm1 * (a2 - 1.0) / denom;
    }
    // Top plate combined with the pile below.
    const double denom = 1.0 - Rsub * r;
    out.transmittance[i] = static_cast<float>(Ta * Tsub / denom);
    out.reflectance[i] = static_cast<float>(Ra + Ta * Rsub * t / denom);
  }
  return out;
}

// Féret et al. 2017, eq. (1): K = (Cab·k_Cab + Car·k_Car + Ant·k_Anth + Cbrown·k_Brown + Cw·k_Cw
// + Cm·k_Cm) / N, then the plate model.
LeafOptics prospect_d(const ProspectParams& p) {
  for (const float c : {p.Cab, p.Car, p.Ant, p.Cbrown, p.Cw, p.Cm})
    if (!(c >= 0.0f) || !std::isfinite(c))
      throw Error("PROSPECT: pigment, water and dry-matter contents must be finite and ≥ 0");
  const ProspectDTable& tab = prospect_d_table();
  std::vector<double> kall(kSamples);
  const double N = p.N;
  for (size_t i = 0; i < kSamples; ++i)
    kall[i] = (p.Cab * tab.k_cab[i] + p.Car * tab.k_car[i] + p.Ant * tab.k_ant[i] + p.Cbrown * tab.k_brown[i] +
               p.Cw * tab.k_cw[i] + p.Cm * tab.k_cm[i]) /
              N;
  return prospect_plate_model(tab.lambda_nm, tab.n, kall, N);
}

}  // namespace sylva
