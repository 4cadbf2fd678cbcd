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

CieSkyShape::CieSkyShape(int type, const Vec3& sun_dir) : sun_dir_(sun_dir) {
  const CieSkyCoefficients& k = cie_sky_table().at(static_cast<size_t>(type - 1));
  a_ = k.a;
  b_ = k.b;
  c_ = k.c;
  d_ = k.d;
  e_ = k.e;
  exp_d_half_pi_ = exp_fast(k.d * kPi / 2);
  const float cos_zs = std::clamp(sun_dir.z, -1.0f, 1.0f);
  inv_zenith_ = 1.0f / (indicatrix(acos_fast(cos_zs), cos_zs) * gradation(1.0f));
}

float CieSkyShape::operator()(const Vec3& dir) const {
  if (dir.z <= 0) return 0.0f;
  const float cos_chi = std::clamp(glm::dot(dir, sun_dir_), -1.0f, 1.0f);
  const float value = indicatrix(acos_fast(cos_chi), cos_chi) * gradation(dir.z) * inv_zenith_;
  return std::max(0.0f, value);
}

float cie_sky_relative_luminance(int type, const Vec3& dir, const Vec3& sun_dir) {
  return CieSkyShape(type, sun_dir)(dir);
}

void CieSky::prepare(const Vec3& sun_dir) { shape_ = CieSkyShape(type, sun_dir); }

float CieSky::relative_radiance(const Vec3& dir, const Vec3& sun_dir) const {
  return shape_ && shape_->sun_direction() == sun_dir ? (*shape_)(dir) : cie_sky_relative_luminance(type, dir, sun_dir);
}

CieSky CieSky::create(const Params& params) {
  CieSky sky;
  sky.type = static_cast<int>(params.integer("type", sky.type, 1, 15));
  return sky;
}

}  // namespace sylva
