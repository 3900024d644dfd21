// Robust statistics for comparing a model with a small measured set that holds gross errors:
// median and MAD scale, the modified z-score rule for gross errors, and the test of whether the
// measurements respond to their measured inputs as a model does.
//
// Why: the lab's 28 cylinder releases (paper Appendix A) hold a few values far outside the rest
// (omega_out -77.8 and -76.4 rad/s against a core of -44 to -32). Means and standard deviations
// are then set by those few values; a model matched to the lab's mean and sd is matched to them.
// The median and the MAD are not (breakdown point 50 %).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace ricochet::stats {

/// Median and MAD scale of one sample. mad_sd = 1.4826 * median |x - median|, the MAD scaled to
/// estimate the standard deviation of a normal sample (Rousseeuw & Croux 1993, JASA 88:1273).
/// NaN values are skipped; an empty sample gives n = 0 and NaN fields.
struct RobustSummary {
  std::size_t n = 0;
  double median = 0, mad_sd = 0;
};
RobustSummary robust_summarize(std::span<const double> x);

/// Modified z-scores M_i = 0.6745 (x_i - median) / MAD (Iglewicz & Hoaglin 1993, "How to detect
/// and handle outliers", ASQC Basic References in Quality Control 16). NaN for NaN inputs, and
/// for every value when MAD = 0.
std::vector<double> modified_z_scores(std::span<const double> x);

/// The gross-error threshold of Iglewicz & Hoaglin (1993): |M_i| > 3.5.
inline constexpr double kGrossErrorThreshold = 3.5;

/// Gross-error flags over several columns of one measured set (e.g. the six velocities of each
/// release): a row is flagged when any column's modified z-score exceeds `threshold` in absolute
/// value. The rule looks only at the measurements, never at a model, so it can be applied before
/// any comparison. `why[i]` lists "column (M = value)" for each exceedance of row i.
/// Throws std::invalid_argument if the columns differ in length or names and columns differ in
/// count, or threshold is not positive.
struct GrossErrors {
  std::vector<bool> flagged;
  std::vector<std::string> why;
  std::size_t count = 0;  ///< flagged rows
};
GrossErrors flag_gross_errors(std::span<const std::vector<double>> columns,
                              std::span<const std::string> names,
                              double threshold = kGrossErrorThreshold);

/// Does a measured set respond to its measured input as a model does? For paired (input, output)
/// samples of the model and of the measurements, the least-squares slope of output on input on
/// each side with its standard error, and the two-sided test of equal slopes,
/// t = (b_model - b_measured) / sqrt(se_model^2 + se_measured^2), Student with n_measured - 2
/// degrees of freedom. Output noise widens se but does not bias a slope; noise in the measured
/// INPUT attenuates the measured slope by the reliability ratio var(true input) / var(measured
/// input) (regression dilution: Fuller 1987, Measurement Error Models, section 1.1), so
/// `reliability` = b_measured / b_model estimates the share of the measured input's variance
/// that is a real change of input. A model run at the measured inputs has the full slope;
/// measurements whose input scatter is reading noise have a slope near 0. Pearson's r of each
/// side is given for information. NaN fields with fewer than 4 pairs on a side or a zero model
/// slope.
struct ResponseCheck {
  double slope_model = 0, se_model = 0, slope_measured = 0, se_measured = 0;
  double reliability = 0;
  double r_model = 0, r_measured = 0;
  std::size_t n_model = 0, n_measured = 0;
  double t = 0, p_value = 1;
};
ResponseCheck compare_responses(std::span<const double> model_in, std::span<const double> model_out,
                                std::span<const double> measured_in,
                                std::span<const double> measured_out);

}  // namespace ricochet::stats
