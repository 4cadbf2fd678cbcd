// Planck's law and brightness temperature (core/planck.h): the Stefan–Boltzmann total, Wien's
// peak, a tabulated value, and the band inversion's round trip and its limit for a narrow band.

#include "core/error.h"
#include "core/planck.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace sylva {
namespace {

namespace planck_test {

// A flat response over [lo, hi] nm with `n` points.
struct Box {
  std::vector<double> lambda, weight;
  Box(double lo, double hi, int n) {
    for (int i = 0; i < n; ++i) {
      lambda.push_back(lo + (hi - lo) * i / (n - 1));
      weight.push_back(1.0);
    }
  }
  SpectralResponse response() const { return {lambda, weight}; }
};

}  // namespace planck_test

TEST(Planck, IntegratesToStefanBoltzmann) {
  // ∫ B_λ dλ over all wavelengths = σT⁴/π: midpoint rule in log λ from 100 nm to 1 mm.
  for (const double t : {250.0, 300.0, 1000.0, 5772.0}) {
    double sum = 0;
    constexpr int kSteps = 200000;
    const double a = std::log(100.0), b = std::log(1e6);
    for (int i = 0; i < kSteps; ++i) {
      const double l = std::exp(a + (b - a) * (i + 0.5) / kSteps);
      sum += planck_radiance(l, t) * l * (b - a) / kSteps;
    }
    const double expected = kStefanBoltzmann * std::pow(t, 4) / M_PI;
    EXPECT_NEAR(sum / expected, 1.0, 1e-5) << t << " K";
  }
}

TEST(Planck, PeaksWhereWienSays) {
  // λ_max = b / T, b = 2.897771955e-3 m·K (CODATA 2018).
  for (const double t : {300.0, 1500.0}) {
    const double peak = 2.897771955e6 / t;  // nm
    EXPECT_GT(planck_radiance(peak, t), planck_radiance(peak * 0.999, t));
    EXPECT_GT(planck_radiance(peak, t), planck_radiance(peak * 1.001, t));
  }
}

TEST(Planck, MatchesATabulatedValueAndItsDerivative) {
  // 10 µm, 300 K: 9.9240 W·m⁻²·sr⁻¹·µm⁻¹ (from 2hc²/λ⁵/(exp(hc/λkT) − 1) with CODATA values).
  EXPECT_NEAR(planck_radiance(10000.0, 300.0) * 1e3, 9.9240, 1e-3);
  // The derivative against a central difference.
  for (const double l : {4000.0, 10000.0}) {
    const double h = 1e-3;
    const double numeric = (planck_radiance(l, 300.0 + h) - planck_radiance(l, 300.0 - h)) / (2 * h);
    EXPECT_NEAR(planck_radiance_dt(l, 300.0) / numeric, 1.0, 1e-7) << l;
  }
  EXPECT_EQ(planck_radiance(10000.0, 0.0), 0.0);
}

TEST(Planck, BrightnessTemperatureInvertsTheBandRadiance) {
  const planck_test::Box lwir(8000, 12000, 81), mwir(3000, 5000, 41), tirs(10600, 11190, 60);
  for (const planck_test::Box* band : {&lwir, &mwir, &tirs})
    for (const double t : {200.0, 273.15, 300.0, 350.0, 900.0}) {
      const double l = band_planck_radiance(band->response(), t);
      EXPECT_NEAR(brightness_temperature(band->response(), l), t, 1e-6 * t) << t << " K";
    }
  // A grey body's BT is below its kinetic temperature and rises with emissivity.
  const double bt90 = brightness_temperature(lwir.response(), 0.90 * band_planck_radiance(lwir.response(), 300.0));
  const double bt98 = brightness_temperature(lwir.response(), 0.98 * band_planck_radiance(lwir.response(), 300.0));
  EXPECT_LT(bt90, bt98);
  EXPECT_LT(bt98, 300.0);
  EXPECT_EQ(brightness_temperature(lwir.response(), 0.0), 0.0);
}

TEST(Planck, ANarrowBandsTemperatureIsTheMonochromaticOne) {
  // Over a 1 nm band the band radiance is B at its centre, so the BT is Planck's inverse there:
  // T = c2 / (λ ln(1 + c1L / (λ⁵ L))).
  const planck_test::Box narrow(10999.5, 11000.5, 3);
  const double radiance_nm = 8.0e-3;  // W·m⁻²·sr⁻¹·nm⁻¹
  const double lambda = 11000e-9;
  const double expected = kPlanckC2 / (lambda * std::log1p(kPlanckC1L / (std::pow(lambda, 5) * radiance_nm * 1e9)));
  EXPECT_NEAR(brightness_temperature(narrow.response(), radiance_nm), expected, 1e-4);
}

TEST(Planck, BadResponsesAreRefused) {
  const std::vector<double> l = {8000, 9000}, zero = {0, 0}, negative = {1, -1}, one = {1};
  EXPECT_THROW(check_response({l, zero}, "b"), Error);
  EXPECT_THROW(check_response({l, negative}, "b"), Error);
  EXPECT_THROW(check_response({one, one}, "b"), Error);
  const std::vector<double> backwards = {9000, 8000}, w = {1, 1};
  EXPECT_THROW(check_response({backwards, w}, "b"), Error);
  EXPECT_NO_THROW(check_response({l, w}, "b"));
}

}  // namespace
}  // namespace sylva
