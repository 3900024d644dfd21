#include "diagnosis/scatter.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>

#include "stats/stats.hpp"

namespace ricochet::diagnosis {
namespace {

// Negative log-likelihood of the held-out residuals under measurement variances `s` plus the
// parameter scatter tau (scatter.hpp), up to a constant.
struct Likelihood {
  std::vector<Eigen::VectorXd> r;               // per release: residuals of used observables
  std::vector<Eigen::VectorXd> s;               // per release: measurement variances
  std::vector<std::vector<Eigen::VectorXd>> j;  // per release, per parameter: derivatives

  double nll(const std::vector<double>& tau) const {
    double total = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      Eigen::MatrixXd cov = s[i].asDiagonal();
      for (std::size_t p = 0; p < tau.size(); ++p)
        cov.noalias() += tau[p] * tau[p] * j[i][p] * j[i][p].transpose();
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(cov);
      const Eigen::VectorXd d = ldlt.vectorD();
      double logdet = 0;
      for (Eigen::Index k = 0; k < d.size(); ++k) logdet += std::log(std::max(d[k], 1e-300));
      total += 0.5 * (logdet + r[i].dot(ldlt.solve(r[i])));
    }
    return total;
  }
};

// Cyclic coordinate descent, golden-section search of each tau_j over [0, hi_j].
std::vector<double> minimise(const Likelihood& L, const std::vector<double>& hi) {
  std::vector<double> tau(hi.size(), 0.0);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int cycle = 0; cycle < 4; ++cycle) {
    for (std::size_t p = 0; p < tau.size(); ++p) {
      auto f = [&](double x) {
        std::vector<double> t = tau;
        t[p] = x;
        return L.nll(t);
      };
      double a = 0, b = hi[p];
      double c = b - g * (b - a), d = a + g * (b - a);
      double fc = f(c), fd = f(d);
      for (int it = 0; it < 40; ++it) {
        if (fc < fd) {
          b = d, d = c, fd = fc;
          c = b - g * (b - a), fc = f(c);
        } else {
          a = c, c = d, fc = fd;
          d = a + g * (b - a), fd = f(d);
        }
      }
      const double best = 0.5 * (a + b);
      // Keep the boundary tau = 0 when it is at least as likely (no scatter).
      tau[p] = f(0.0) <= f(best) ? 0.0 : best;
    }
  }
  return tau;
}

}  // namespace

PopulationScatter population_scatter(const Model& warm, const Shape& shape, const ImpactSet& set,
                                     const Assessment& base, const NoiseFloor& floor,
                                     const AssessOptions& options) {
  const AssessOptions o = resolve_scale(set, options);
  PopulationScatter out;
  const std::size_t n = set.size();
  if (floor.variance.size() != n || n < 4) return out;
  // The parameters the fits on this set calibrate (kn too with contact terms): the probes'.
  const std::vector<std::size_t> cal = calibration_model_for(warm, set, o).calibrated_indices();
  std::vector<int> obs;
  for (int k = 0; k < kObservables; ++k)
    if (base.use[k]) obs.push_back(k);
  const auto p0 = predict_observables(warm, shape, warm.values(), set, o);
  Likelihood L;
  L.r.assign(n, Eigen::VectorXd(static_cast<Eigen::Index>(obs.size())));
  L.s.assign(n, Eigen::VectorXd(static_cast<Eigen::Index>(obs.size())));
  L.j.assign(n, std::vector<Eigen::VectorXd>(
                    cal.size(), Eigen::VectorXd(static_cast<Eigen::Index>(obs.size()))));
  const double n_train = static_cast<double>(n) * static_cast<double>(base.folds - 1) /
                         static_cast<double>(base.folds);
  const double inflate = 1.0 + static_cast<double>(cal.size()) / std::max(1.0, n_train);
  std::vector<double> hi;
  const std::vector<ParameterProbe> probes = probe_calibrated(warm, shape, set, o);
  for (std::size_t c = 0; c < probes.size(); ++c) {
    const ParameterProbe& pr = probes[c];
    const std::size_t jj = pr.index;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = 0; k < obs.size(); ++k) {
        const double v = (pr.predictions[i].value[obs[k]] - p0[i].value[obs[k]]) / pr.step;
        L.j[i][c][static_cast<Eigen::Index>(k)] = std::isfinite(v) ? v : 0.0;
      }
    hi.push_back(0.5 * pr.range);
    out.names.emplace_back(warm.spec(jj).name);
    out.units.emplace_back(warm.spec(jj).unit);
    out.value.push_back(warm.values()[jj]);
  }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < obs.size(); ++k) {
      const auto kk = static_cast<Eigen::Index>(k);
      const double r = base.heldout.residual[i][obs[k]];
      L.r[i][kk] = std::isfinite(r) ? r : 0.0;
      L.s[i][kk] = std::max(floor.variance[i][obs[k]] * inflate, 1e-30);
    }
  out.sd = minimise(L, hi);
  const double best = L.nll(out.sd);
  for (std::size_t c = 0; c < cal.size(); ++c) {
    std::vector<double> t = out.sd;
    t[c] = 0.0;
    out.identified.push_back(L.nll(t) - best >= 0.5);
  }
  out.lr = std::max(0.0, 2.0 * (L.nll(std::vector<double>(cal.size(), 0.0)) - L.nll(out.sd)));
  out.p_value =
      cal.empty() ? 1.0 : stats::chi_square_upper_tail(out.lr, static_cast<double>(cal.size()));

  out.floor = floor;
  out.floor.source = floor.source + "+scatter";
  for (std::size_t i = 0; i < n; ++i) {
    double e = 0;
    for (std::size_t k = 0; k < obs.size(); ++k) {
      double extra = 0;
      for (std::size_t c = 0; c < cal.size(); ++c) {
        const double jv = L.j[i][c][static_cast<Eigen::Index>(k)];
        extra += out.sd[c] * out.sd[c] * jv * jv;
      }
      out.floor.variance[i][obs[k]] += extra;
      const double d = error_scale(set.impacts[i], o)[obs[k]];
      out.floor.terms[i][obs[k]] += extra / (d * d);
      e += out.floor.terms[i][obs[k]];
    }
    out.floor.per_release[i] = e;
  }
  out.floor.value = mean_se(out.floor.per_release);
  out.adequacy = adequacy(base, out.floor);
  std::string spread;
  for (std::size_t c = 0; c < cal.size(); ++c)
    spread += fmt::format("{}{} {:.3g} +- {:.2g}{}", spread.empty() ? "" : ", ", out.names[c],
                          out.value[c], out.sd[c], out.units[c] == "-" ? "" : " " + out.units[c]);
  out.floor.description = floor.description + ", plus the release-to-release scatter of " + spread;
  out.description = fmt::format(
      "release-to-release scatter of the parameters (linearised random-effects fit of the "
      "held-out residuals): {} (population value +- between-release SD); likelihood-ratio test "
      "of no scatter: {:.3g}, p = {:.2g}; with it the noise floor is {:.4g} and the held-out "
      "error is {:.2f} x that floor",
      spread, out.lr, out.p_value, out.floor.value.mean, out.adequacy.ratio);
  out.computed = true;
  return out;
}

nlohmann::json to_json(const PopulationScatter& s) {
  if (!s.computed) return nullptr;
  nlohmann::json params = nlohmann::json::object();
  for (std::size_t c = 0; c < s.names.size(); ++c)
    params[s.names[c]] = {{"value", s.value[c]},
                          {"sd", s.sd[c]},
                          {"sd_identified", static_cast<bool>(s.identified[c])},
                          {"unit", s.units[c]}};
  return {{"parameters", params},
          {"likelihood_ratio", s.lr},
          {"p_value", s.p_value},
          {"floor_with_scatter", s.floor.value.mean},
          {"ratio_to_floor_with_scatter", s.adequacy.ratio},
          {"adequate_with_scatter", s.adequacy.adequate},
          {"description", s.description}};
}

}  // namespace ricochet::diagnosis
