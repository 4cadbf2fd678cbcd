#include "core/prospect.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sylva {
namespace {

// Reference tables copied into the repository (tests/data/README.md names their sources).
const std::string kTestData = std::string(SYLVA_SOURCE_DIR) + "/tests/data";

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string field;
  while (std::getline(ss, field, sep)) out.push_back(field);
  return out;
}

// Rows of a numeric whitespace/comma separated file, '#' lines and non-numeric header skipped.
std::vector<std::vector<double>> read_numbers(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::vector<double> row;
    double v = 0;
    while (ss >> v) row.push_back(v);
    if (!row.empty() && ss.eof()) rows.push_back(row);
  }
  return rows;
}

struct ReferenceRow {
  std::string model;
  double N, Cab, Car, Ant, Cbrown, Cw, Cm;
  char quantity;
  std::vector<std::pair<int, double>> values;  // (λ nm, value)
};

std::vector<ReferenceRow> read_reference() {
  std::ifstream in(kTestData + "/prospect/prospect_reference_values.csv");
  EXPECT_TRUE(in);
  std::string line;
  std::vector<std::string> header;
  std::vector<ReferenceRow> rows;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) {
      header = split(line, ',');
      continue;
    }
    const auto f = split(line, ',');
    ReferenceRow r;
    r.model = f[0];
    r.N = std::stod(f[1]);
    r.Cab = std::stod(f[2]);
    r.Car = std::stod(f[3]);
    r.Ant = std::stod(f[4]);
    r.Cbrown = std::stod(f[5]);
    r.Cw = std::stod(f[6]);
    r.Cm = std::stod(f[7]);
    r.quantity = f[8].at(0);
    for (size_t c = 9; c < header.size() && c < f.size(); ++c) {
      const std::string& h = header[c];
      if (h.size() > 2 && h.substr(h.size() - 2) == "nm")
        r.values.emplace_back(std::stoi(h.substr(0, h.size() - 2)), std::stod(f[c]));
    }
    rows.push_back(r);
  }
  return rows;
}

std::vector<float> grid_400_2500() {
  std::vector<float> l(2101);
  for (size_t i = 0; i < l.size(); ++i) l[i] = 400.0f + static_cast<float>(i);
  return l;
}

TEST(Prospect, ExponentialIntegralKnownValues) {
  // Abramowitz & Stegun table 5.1 / scipy.special.exp1.
  EXPECT_NEAR(exponential_integral_e1(0.1), 1.8229239584193906, 1e-14);
  EXPECT_NEAR(exponential_integral_e1(0.5), 0.5597735947761608, 1e-14);
  EXPECT_NEAR(exponential_integral_e1(1.0), 0.21938393439552029, 1e-14);
  EXPECT_NEAR(exponential_integral_e1(2.0), 0.04890051070806112, 1e-15);
  EXPECT_NEAR(exponential_integral_e1(10.0), 4.156968929685324e-06, 1e-18);
}

TEST(Prospect, TavLimits) {
  // Normal-incidence-like limit for n = 1: a perfect interface.
  EXPECT_NEAR(prospect_tav(90.0, 1.0001), 1.0, 1e-3);
  // Isotropic transmissivity of n = 1.5 is about 0.908 (Allen 1973); the 40° cone transmits more.
  EXPECT_NEAR(prospect_tav(90.0, 1.5), 0.9078, 5e-4);
  EXPECT_GT(prospect_tav(40.0, 1.5), prospect_tav(90.0, 1.5));
}

TEST(Prospect, MatchesReferenceProspectD) {
  const auto rows = read_reference();
  int checked = 0;
  double max_err = 0;
  for (const ReferenceRow& r : rows) {
    if (r.model != "PROSPECT-D") continue;
    ProspectParams p;
    p.N = static_cast<float>(r.N);
    p.Cab = static_cast<float>(r.Cab);
    p.Car = static_cast<float>(r.Car);
    p.Ant = static_cast<float>(r.Ant);
    p.Cbrown = static_cast<float>(r.Cbrown);
    p.Cw = static_cast<float>(r.Cw);
    p.Cm = static_cast<float>(r.Cm);
    const LeafOptics o = prospect_d(p);
    ASSERT_EQ(o.lambda_nm.size(), 2101u);
    EXPECT_EQ(o.lambda_nm.front(), 400.0f);
    EXPECT_EQ(o.lambda_nm.back(), 2500.0f);
    ASSERT_FALSE(r.values.empty());
    for (const auto& [nm, expected] : r.values) {
      const size_t i = static_cast<size_t>(nm - 400);
      const float got = r.quantity == 'R' ? o.reflectance[i] : o.transmittance[i];
      // The reference is printed to 4 decimals.
      EXPECT_NEAR(got, expected, 5.1e-5) << r.quantity << " at " << nm << " nm, N=" << r.N;
      max_err = std::max(max_err, std::abs(got - expected));
      ++checked;
    }
  }
  EXPECT_EQ(checked, 8 * 11);
  RecordProperty("max_abs_error", std::to_string(max_err));
  std::printf("PROSPECT-D max |error| vs reference (4-decimal values): %.6g\n", max_err);
}

TEST(Prospect, PlateModelMatchesProspect5Reference) {
  // prospect5_spectra.txt columns: n, k_Cab, k_Car, k_Brown, k_Cw, k_Cm (no header, 400..2500 nm).
  const auto tab = read_numbers(kTestData + "/prospect/prospect5_spectra.txt");
  ASSERT_EQ(tab.size(), 2101u);
  const auto rows = read_reference();
  int checked = 0;
  for (const ReferenceRow& r : rows) {
    if (r.model != "PROSPECT-5") continue;
    std::vector<double> n(2101), k(2101);
    for (size_t i = 0; i < 2101; ++i) {
      n[i] = tab[i][0];
      k[i] = (r.Cab * tab[i][1] + r.Car * tab[i][2] + r.Cbrown * tab[i][3] + r.Cw * tab[i][4] + r.Cm * tab[i][5]) / r.N;
    }
    const LeafOptics o = prospect_plate_model(grid_400_2500(), n, k, r.N);
    for (const auto& [nm, expected] : r.values) {
      const size_t i = static_cast<size_t>(nm - 400);
      const float got = r.quantity == 'R' ? o.reflectance[i] : o.transmittance[i];
      EXPECT_NEAR(got, expected, 5.1e-5) << "PROSPECT-5 " << r.quantity << " at " << nm;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 2 * 11);
}

TEST(Prospect, PlateModelMatchesProspectProMatlabOracle) {
  // Official Matlab PROSPECT-PRO: N 1.2, Cab 30, Car 10, Ant 1, Cbrown 0, Cw 0.015, Cm 0.009,
  // Prot 0.001, CBC 0.009 (the oracle run includes all three dry-matter terms).
  const auto tab = read_numbers(kTestData + "/prospect/dataSpec_PRO.txt");
  const auto ref =
      read_numbers(kTestData + "/prospect/prospect_pro_matlab_reference_N1.2_Cab30_Car10_Ant1_Cw0.015_Cm0.009.txt");
  ASSERT_EQ(tab.size(), 2101u);
  ASSERT_EQ(ref.size(), 2101u);
  const double N = 1.2;
  std::vector<double> n(2101), k(2101);
  for (size_t i = 0; i < 2101; ++i) {
    const auto& c = tab[i];  // lambda n CHL CAR ANT BROWN EWT LMA PROT CBC
    n[i] = c[1];
    k[i] =
        (30 * c[2] + 10 * c[3] + 1 * c[4] + 0 * c[5] + 0.015 * c[6] + 0.009 * c[7] + 0.001 * c[8] + 0.009 * c[9]) / N;
  }
  const LeafOptics o = prospect_plate_model(grid_400_2500(), n, k, N);
  double max_err = 0;
  for (size_t i = 0; i < 2101; ++i) {
    ASSERT_EQ(ref[i][0], 400.0 + static_cast<double>(i));
    max_err = std::max(max_err, std::abs(o.reflectance[i] - ref[i][1]));
    max_err = std::max(max_err, std::abs(o.transmittance[i] - ref[i][2]));
  }
  // Results are stored as float; the physics is double.
  EXPECT_LT(max_err, 1e-6);
  std::printf("PROSPECT-PRO max |error| vs Matlab oracle (all 2101 λ): %.3g\n", max_err);
}

TEST(Prospect, EnergyConservedEverywhere) {
  for (const float N : {1.0f, 1.2f, 1.5f, 2.5f, 3.5f})
    for (const float cab : {0.0f, 10.0f, 40.0f, 100.0f}) {
      ProspectParams p;
      p.N = N;
      p.Cab = cab;
      p.Ant = cab / 20;
      const LeafOptics o = prospect_d(p);
      for (size_t i = 0; i < o.lambda_nm.size(); ++i) {
        ASSERT_GE(o.reflectance[i], 0.0f);
        ASSERT_GE(o.transmittance[i], 0.0f);
        ASSERT_LE(o.reflectance[i] + o.transmittance[i], 1.0f + 1e-6f) << o.lambda_nm[i];
      }
    }
}

TEST(Prospect, NoAbsorptionConservesEnergy) {
  ProspectParams p;
  p.Cab = p.Car = p.Ant = p.Cbrown = p.Cw = p.Cm = 0;
  const LeafOptics o = prospect_d(p);
  for (size_t i = 0; i < o.lambda_nm.size(); ++i) EXPECT_NEAR(o.reflectance[i] + o.transmittance[i], 1.0f, 1e-5f);
}

TEST(Prospect, MoreChlorophyllDarkensGreen) {
  float previous = 2.0f;
  for (const float cab : {5.0f, 20.0f, 40.0f, 80.0f}) {
    ProspectParams p;
    p.Cab = cab;
    const LeafOptics o = prospect_d(p);
    const float green = o.reflectance[550 - 400];
    EXPECT_LT(green, previous) << "Cab " << cab;
    previous = green;
  }
}

TEST(Prospect, MoreWaterDarkensSwir) {
  ProspectParams dry, wet;
  dry.Cw = 0.002f;
  wet.Cw = 0.03f;
  EXPECT_LT(prospect_d(wet).reflectance[1450 - 400], prospect_d(dry).reflectance[1450 - 400]);
  EXPECT_LT(prospect_d(wet).reflectance[1940 - 400], prospect_d(dry).reflectance[1940 - 400]);
}

TEST(Prospect, RejectsInvalidParameters) {
  ProspectParams p;
  p.N = 0.5f;
  EXPECT_THROW(prospect_d(p), Error);
  p = {};
  p.Cab = -1;
  EXPECT_THROW(prospect_d(p), Error);
  p = {};
  p.Cw = std::nanf("");
  EXPECT_THROW(prospect_d(p), Error);
}

}  // namespace
}  // namespace sylva
