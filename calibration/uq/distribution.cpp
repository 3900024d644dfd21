#include "uq/distribution.hpp"

#include <openturns/OT.hxx>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.hpp"

namespace ricochet::uq {

struct Distribution::Impl {
  OT::Distribution dist;
  bool uniform = false;
};

Distribution Distribution::uniform(double lo, double hi) {
  if (!(lo < hi) || !std::isfinite(lo) || !std::isfinite(hi))
    throw std::invalid_argument("uniform range needs LO < HI (got " + std::to_string(lo) + ", " +
                                std::to_string(hi) + ")");
  Distribution d;
  d.impl_ = std::make_shared<Impl>(Impl{OT::Uniform(lo, hi), true});
  return d;
}

Distribution Distribution::fitted(std::span<const double> sample, double lo, double hi) {
  std::vector<double> v;
  for (double x : sample)
    if (std::isfinite(x)) v.push_back(x);
  std::vector<double> distinct = v;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  if (distinct.size() < 3)
    throw std::invalid_argument("fitting a distribution needs at least 3 distinct values");
  OT::Sample s(v.size(), 1);
  for (std::size_t i = 0; i < v.size(); ++i) s(i, 0) = v[i];
  OT::Collection<OT::DistributionFactory> factories;
  factories.add(OT::NormalFactory());
  factories.add(OT::BetaFactory());
  factories.add(OT::LogNormalFactory());
  factories.add(OT::TriangularFactory());
  factories.add(OT::UniformFactory());
  OT::Scalar bic = 0;
  // A family that cannot fit the sample (e.g. a Triangular mode outside its range) is skipped;
  // OpenTURNS would warn on stderr about it, which is noise for the user: silence warnings.
  const OT::Log::Severity flags = OT::Log::Flags();
  OT::Log::Show(flags & ~OT::Log::WARN);
  OT::Distribution best;
  try {
    best = OT::FittingTest::BestModelBIC(s, factories, bic);
  } catch (...) {
    OT::Log::Show(flags);
    throw;
  }
  OT::Log::Show(flags);
  // Truncate to the parameter's bounds (a fitted Normal has infinite support).
  const double a = std::max(lo, best.getRange().getLowerBound()[0]);
  const double b = std::min(hi, best.getRange().getUpperBound()[0]);
  Distribution d;
  if (a > best.getRange().getLowerBound()[0] || b < best.getRange().getUpperBound()[0])
    d.impl_ = std::make_shared<Impl>(Impl{OT::TruncatedDistribution(best, a, b), false});
  else
    d.impl_ = std::make_shared<Impl>(Impl{best, false});
  return d;
}

double Distribution::quantile(double p) const {
  return impl_->dist.computeQuantile(std::clamp(p, 0.0, 1.0))[0];
}
double Distribution::cdf(double x) const {
  return impl_->dist.computeCDF(x);
}
double Distribution::lower() const {
  return impl_->dist.getRange().getLowerBound()[0];
}
double Distribution::upper() const {
  return impl_->dist.getRange().getUpperBound()[0];
}
std::string Distribution::description() const {
  return impl_->dist.__str__();
}
bool Distribution::is_uniform() const {
  return impl_->uniform;
}

std::optional<std::pair<double, double>> paper_range(ParameterRole role) {
  switch (role) {
    case ParameterRole::kRestitution:
      return std::make_pair(0.05, 0.25);
    case ParameterRole::kFrictionCap:
      return std::make_pair(0.0, 0.6);
    case ParameterRole::kRollingCap:
      return std::make_pair(0.0, 0.3);
    default:
      return std::nullopt;
  }
}

std::map<std::string, std::pair<double, double>> paper_ranges(const Model& model) {
  std::map<std::string, std::pair<double, double>> out;
  for (std::size_t i = 0; i < model.parameter_count(); ++i)
    if (const auto r = paper_range(model.spec(i).role)) out[std::string(model.spec(i).name)] = *r;
  return out;
}

std::pair<std::string, std::pair<double, double>> parse_range(const std::string& text,
                                                              const std::string& option) {
  const auto eq = text.find('=');
  const auto colon = text.find(':', eq == std::string::npos ? 0 : eq);
  if (eq == std::string::npos || colon == std::string::npos || eq == 0)
    throw InputError("command line", 0, option,
                     "expected NAME=LO:HI (e.g. en2=0.05:0.25), got '" + text + "'");
  const std::string name = text.substr(0, eq);
  double lo = 0, hi = 0;
  try {
    std::size_t n1 = 0, n2 = 0;
    const std::string a = text.substr(eq + 1, colon - eq - 1), b = text.substr(colon + 1);
    lo = std::stod(a, &n1);
    hi = std::stod(b, &n2);
    if (n1 != a.size() || n2 != b.size()) throw std::invalid_argument("trailing characters");
  } catch (const std::exception&) {
    throw InputError("command line", 0, option, "LO and HI must be numbers in '" + text + "'");
  }
  if (!(lo < hi)) throw InputError("command line", 0, option, "needs LO < HI in '" + text + "'");
  return {name, {lo, hi}};
}

}  // namespace ricochet::uq
