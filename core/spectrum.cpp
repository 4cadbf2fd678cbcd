#include "core/spectrum.h"

#include "core/data_path.h"
#include "core/table.h"

#include <cmath>

namespace sylva {

DenseSpectrum DenseSpectrum::constant(float value) {
  DenseSpectrum s;
  std::fill(s.values_.begin(), s.values_.end(), value);
  return s;
}

DenseSpectrum DenseSpectrum::from_samples(const std::vector<double>& lambda_nm, const std::vector<double>& value,
                                          Extrapolate outside) {
  std::vector<double> xs, ys;
  for (size_t i = 0; i < lambda_nm.size() && i < value.size(); ++i)
    if (std::isfinite(lambda_nm[i]) && std::isfinite(value[i])) {
      xs.push_back(lambda_nm[i]);
      ys.push_back(value[i]);
    }
  DenseSpectrum s;
  if (xs.empty()) return s;
  // Piecewise-linear interpolant, box-filtered over [λ-0.5, λ+0.5] by 8-point midpoint averaging.
  size_t seg = 0;
  auto interp = [&](double x) -> double {
    if (x < xs.front()) return outside == Extrapolate::Clamp ? ys.front() : 0.0;
    if (x > xs.back()) return outside == Extrapolate::Clamp ? ys.back() : 0.0;
    while (seg + 1 < xs.size() && xs[seg + 1] < x) ++seg;
    while (seg > 0 && xs[seg] > x) --seg;
    if (seg + 1 >= xs.size()) return ys.back();
    const double t = (x - xs[seg]) / std::max(1e-12, xs[seg + 1] - xs[seg]);
    return ys[seg] + t * (ys[seg + 1] - ys[seg]);
  };
  for (int i = 0; i < kLambdaSamples; ++i) {
    const double l = grid_lambda(i);
    double sum = 0;
    constexpr int kSub = 8;
    for (int k = 0; k < kSub; ++k) sum += interp(l - 0.5 + (k + 0.5) / kSub);
    s.values_[i] = static_cast<float>(sum / kSub);
  }
  return s;
}

double DenseSpectrum::integral() const {
  double sum = 0;
  for (int i = 0; i + 1 < kLambdaSamples; ++i) sum += 0.5 * (values_[i] + values_[i + 1]);
  return sum;
}

double DenseSpectrum::integral_product(const DenseSpectrum& other) const { return (*this * other).integral(); }

float DenseSpectrum::min_value() const { return *std::min_element(values_.begin(), values_.end()); }
float DenseSpectrum::max_value() const { return *std::max_element(values_.begin(), values_.end()); }

DenseSpectrum& DenseSpectrum::operator*=(float s) {
  for (float& v : values_) v *= s;
  return *this;
}

DenseSpectrum operator*(const DenseSpectrum& a, const DenseSpectrum& b) {
  DenseSpectrum r;
  for (int i = 0; i < kLambdaSamples; ++i) r.values_[i] = a.values_[i] * b.values_[i];
  return r;
}
DenseSpectrum operator+(const DenseSpectrum& a, const DenseSpectrum& b) {
  DenseSpectrum r;
  for (int i = 0; i < kLambdaSamples; ++i) r.values_[i] = a.values_[i] + b.values_[i];
  return r;
}
DenseSpectrum operator-(const DenseSpectrum& a, const DenseSpectrum& b) {
  DenseSpectrum r;
  for (int i = 0; i < kLambdaSamples; ++i) r.values_[i] = a.values_[i] - b.values_[i];
  return r;
}

DenseSpectrum load_spectrum(const std::filesystem::path& table, const std::string& column, Extrapolate outside) {
  const Table t = read_table(table);
  return DenseSpectrum::from_samples(t.columns[0], t.columns[t.column(column)], outside);
}

namespace {
struct StandardSpectra {
  DenseSpectrum x, y, z, direct, global;
  StandardSpectra() {
    const Table cmf = read_table(data_file("cie1931_2deg_cmf_1nm.csv"));
    x = DenseSpectrum::from_samples(cmf.columns[0], cmf.columns[cmf.column("xbar")], Extrapolate::Zero);
    y = DenseSpectrum::from_samples(cmf.columns[0], cmf.columns[cmf.column("ybar")], Extrapolate::Zero);
    z = DenseSpectrum::from_samples(cmf.columns[0], cmf.columns[cmf.column("zbar")], Extrapolate::Zero);
    const Table sun = read_table(data_file("astm_g173_03_reference_spectra.csv"));
    direct = DenseSpectrum::from_samples(sun.columns[0], sun.columns[sun.column("direct_circumsolar_W_m2_nm")],
                                         Extrapolate::Zero);
    global = DenseSpectrum::from_samples(sun.columns[0], sun.columns[sun.column("global_tilt_37deg_W_m2_nm")],
                                         Extrapolate::Zero);
  }
};
const StandardSpectra& standard() {
  static const StandardSpectra s;
  return s;
}
}  // namespace

const DenseSpectrum& cie_x() { return standard().x; }
const DenseSpectrum& cie_y() { return standard().y; }
const DenseSpectrum& cie_z() { return standard().z; }
const DenseSpectrum& astm_g173_direct() { return standard().direct; }
const DenseSpectrum& astm_g173_global() { return standard().global; }

DenseSpectrum astm_g173_diffuse() {
  const float cos_incidence = std::cos(radians(48.19f - 37.0f));
  DenseSpectrum d = astm_g173_global();
  const DenseSpectrum& b = astm_g173_direct();
  for (int i = 0; i < kLambdaSamples; ++i) d[i] = std::max(0.0f, d[i] - cos_incidence * b[i]);
  return d;
}

std::optional<DenseSpectrum> named_spectrum(std::string_view name) {
  if (name == "astm-g173-direct") return astm_g173_direct();
  if (name == "astm-g173-diffuse") return astm_g173_diffuse();
  if (name == "astm-g173-global") return astm_g173_global();
  return std::nullopt;
}

}  // namespace sylva
