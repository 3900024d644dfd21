// Paper Table 2 as printed (Garcia et al. 2020), shared by the library and command tests.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace ricochet::test {

struct PrintedColumn {
  const char* name;   // impact-set feature name
  double mean, std;   // 2 decimals as printed [m/s or rad/s]
  double cv_percent;  // integer percent as printed
  double min, max;    // 2 decimals as printed
  // Known misprints, checked as such rather than skipped:
  bool mean_misprinted = false;     // printed mean is not Appendix A's mean rounded
  bool cv_sign_misprinted = false;  // printed CV has the wrong sign (mean < 0)
};

// Columns in the order of Table 2: V_in^x, V_out^x, V_in^y, V_out^y, omega_in, omega_out.
inline constexpr std::array<PrintedColumn, 6> kTable2Cylinders = {{
    {"vin_x", 2.87, 0.21, 7, 2.18, 3.18},
    // Appendix A sums to 85.55 m/s over 28 releases: mean 3.05536, which rounds to 3.06.
    {"vout_x", 3.05, 0.28, 9, 2.42, 3.87, true, false},
    {"vin_y", -2.34, 0.19, -8, -2.69, -1.91},
    {"vout_y", 0.86, 0.17, 20, 0.46, 1.14},
    {"win", -65.03, 5.85, -9, -71.57, -44.06},
    {"wout", -42.30, 10.68, -25, -77.82, -32.21},
}};

// Table 2's triangle block is all 31 releases (its caption says 19, the count with
// V_in^x < 3.5 m/s; the statistics only match the full set).
inline constexpr std::array<PrintedColumn, 6> kTable2Triangles = {{
    {"vin_x", 3.76, 0.95, 25, 2.30, 5.69},
    {"vout_x", 2.64, 1.19, 45, 0.24, 5.87},
    {"vin_y", -2.73, 0.84, -31, -4.34, -1.45},
    {"vout_y", 0.51, 0.26, 52, 0.18, 1.19},
    {"win", -39.70, 17.08, -43, -68.49, -13.34},
    // Printed "39 %" although the mean is negative: std / mean = -0.387.
    {"wout", -17.32, 6.70, 39, -27.65, 2.41, false, true},
}};

// Half a unit of the last printed digit (plus rounding slack of the binary representation).
inline constexpr double kHalf2Dec = 0.005 + 1e-9;
inline constexpr double kHalfPercent = 0.5 + 1e-9;

/// Checks one computed column against its printed Table 2 values, to the printed digits.
inline void expect_table2_column(const PrintedColumn& p, double mean, double std, double cv,
                                 double min, double max) {
  SCOPED_TRACE(p.name);
  if (p.mean_misprinted) {
    // Off by less than one printed digit, but beyond rounding: record the misprint.
    EXPECT_NEAR(mean, p.mean, 0.01);
    EXPECT_GT(std::abs(mean - p.mean), kHalf2Dec);
  } else {
    EXPECT_NEAR(mean, p.mean, kHalf2Dec);
  }
  EXPECT_NEAR(std, p.std, kHalf2Dec);
  if (p.cv_sign_misprinted) {
    EXPECT_LT(mean, 0);
    EXPECT_LT(cv, 0);
    EXPECT_NEAR(-100.0 * cv, p.cv_percent, kHalfPercent);
  } else {
    EXPECT_NEAR(100.0 * cv, p.cv_percent, kHalfPercent);
  }
  EXPECT_NEAR(min, p.min, kHalf2Dec);
  EXPECT_NEAR(max, p.max, kHalf2Dec);
}

}  // namespace ricochet::test
