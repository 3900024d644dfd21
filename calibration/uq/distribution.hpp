// Input distributions of model parameters for Monte Carlo and Sobol analyses (paper section
// 4.3, Eq. 8, Fig. 15). OpenTURNS does the work and stays out of this header.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "effects/model.hpp"

namespace ricochet::uq {

/// A 1-D distribution of one parameter value.
class Distribution {
 public:
  /// Uniform on [lo, hi] (paper Eq. 8). Throws std::invalid_argument unless lo < hi.
  static Distribution uniform(double lo, double hi);
  /// Fitted to a sample (e.g. the per-release calibrated values): the best of Normal, Beta,
  /// LogNormal, Triangular and Uniform by BIC (OpenTURNS FittingTest::BestModelBIC), truncated
  /// to [lo, hi] (the parameter's bounds). Needs at least 3 distinct values.
  static Distribution fitted(std::span<const double> sample, double lo, double hi);

  double quantile(double p) const;  ///< inverse CDF, p in [0, 1]
  double cdf(double x) const;
  double lower() const;  ///< support
  double upper() const;
  std::string description() const;  ///< e.g. "Uniform(a = 0.05, b = 0.25)"
  bool is_uniform() const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
};

/// A varied model parameter and its distribution.
struct ParameterInput {
  std::string name;  ///< model parameter name, e.g. "en2"
  Distribution distribution;
};

/// The paper's uniform range (section 4.3) of a parameter of this role: e_n^2 in [0.05, 0.25]
/// (kRestitution), mu in [0, 0.6] (kFrictionCap), mu_R in [0, 0.3] (kRollingCap); none for the
/// other roles.
std::optional<std::pair<double, double>> paper_range(ParameterRole role);
/// The paper's ranges of `model`'s parameters that have one (paper_range), by parameter name:
/// {en2, mu, muR} for the paper's law.
std::map<std::string, std::pair<double, double>> paper_ranges(const Model& model = Model::paper());

/// The paper's incident state of the Monte Carlo (section 4.3): mean of Operator #2's cylinders,
/// V_in = (2.9 m/s, -2.3 m/s, -65 rad/s).
inline constexpr double kPaperVin[3] = {2.9, -2.3, -65.0};

/// Parses "NAME=LO:HI" (the --range syntax). Throws InputError (field = option) when malformed.
std::pair<std::string, std::pair<double, double>> parse_range(const std::string& text,
                                                              const std::string& option);

}  // namespace ricochet::uq
