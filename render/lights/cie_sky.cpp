#include "render/lights/cie_sky.h"

#include "core/data_path.h"
#include "core/error.h"
#include "core/table.h"

#include <array>

namespace sylva {

namespace {

struct CieSkyCoefficients {
  float a, b, c, d, e;
};

const std::array<CieSkyCoefficients, 15>& cie_sky_table() {
  static const auto table = [] {
    const Table t = read_table(data_file("cie_standard_general_sky_15_types.csv"), true, {"description"});
    std::array<CieSkyCoefficients, 15> out{};
    if (t.rows() != 15) throw Error("CIE sky table: expected 15 rows");
    for (size_t r = 0; r < 15; ++r)
      out[r] = {static_cast<float>(t.columns[t.column("a")][r]), static_cast<float>(t.columns[t.column("b")][r]),
                static_cast<float>(t.columns[t.column("c")][r]), static_cast<float>(t.columns[t.column("d")][r]),
                static_cast<float>(t.columns[t.column("e")][r])};
    return out;
  }();
  return table;
}

}  // namespace

float cie_sky_relative_luminance(int type, const Vec3& dir, const Vec3& sun_dir) {
  if (dir.z <= 0) return 0.0f;
  const CieSkyCoefficients& k = cie_sky_table().at(static_cast<size_t>(type - 1));
  // Gradation φ(Z) = 1 + a·exp(b / cos Z); indicatrix f(χ) = 1 + c·[exp(dχ) − exp(dπ/2)] + e·cos²χ.
  auto gradation = [&](float cos_z) { return 1.0f + k.a * std::exp(k.b / std::max(cos_z, 1e-4f)); };
  auto indicatrix = [&](float chi) {
    return 1.0f + k.c * (std::exp(k.d * chi) - std::exp(k.d * kPi / 2)) + k.e * sqr(std::cos(chi));
  };
  const float chi = safe_acos(glm::dot(dir, sun_dir));
  const float zs = safe_acos(sun_dir.z);
  const float value = indicatrix(chi) * gradation(dir.z) / (indicatrix(zs) * gradation(1.0f));
  return std::max(0.0f, value);
}

CieSky CieSky::create(const Params& params) {
  CieSky sky;
  sky.type = static_cast<int>(params.integer("type", sky.type, 1, 15));
  return sky;
}

}  // namespace sylva
