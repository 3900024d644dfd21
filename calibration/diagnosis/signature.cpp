#include "diagnosis/signature.hpp"

#include <cmath>

namespace ricochet::diagnosis::detail {
namespace {

std::vector<std::pair<std::size_t, int>> rows_of(std::size_t n,
                                                 const std::array<bool, kObservables>& use) {
  std::vector<std::pair<std::size_t, int>> rows;
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < kObservables; ++k)
      if (use[k]) rows.emplace_back(i, k);
  return rows;
}

// Multiplies each release's block of rows (its used observables, contiguous in `rows`) by W.
void whiten_blocks(Eigen::VectorXd& v, const Eigen::MatrixXd& W) {
  const Eigen::Index k = W.rows();
  for (Eigen::Index r = 0; k > 0 && r + k <= v.size(); r += k)
    v.segment(r, k) = W * v.segment(r, k);
}

// The change of the whitened predictions per unit of the parameter step (Directions::whiten).
Eigen::VectorXd scaled_change(const std::vector<ObsPrediction>& a,
                              const std::vector<ObsPrediction>& b, const ImpactSet& set,
                              const std::vector<std::pair<std::size_t, int>>& rows, double step,
                              const Eigen::MatrixXd& whiten, const AssessOptions& o) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto [i, k] = rows[r];
    const double d = error_scale(set.impacts[i], o)[k];
    const double x = (a[i].value[k] - b[i].value[k]) / step / d;
    v[static_cast<Eigen::Index>(r)] = std::isfinite(x) ? x : 0.0;
  }
  whiten_blocks(v, whiten);
  return v;
}

}  // namespace

Directions base_directions(const Model& warm, const Shape& shape, const ImpactSet& set,
                           const Assessment& base, const AssessOptions& o) {
  Directions d;
  d.rows = rows_of(set.size(), base.use);
  // Whitening: the pooled covariance of the releases' scaled in-sample residual vectors.
  Eigen::VectorXd z(static_cast<Eigen::Index>(d.rows.size()));
  for (std::size_t r = 0; r < d.rows.size(); ++r) {
    const auto [i, k] = d.rows[r];
    const double x = base.insample.residual[i][k] / error_scale(set.impacts[i], o)[k];
    z[static_cast<Eigen::Index>(r)] = std::isfinite(x) ? x : 0.0;
  }
  const Eigen::Index k = set.size() > 0 ? static_cast<Eigen::Index>(d.rows.size() / set.size()) : 0;
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(k, k);
  for (Eigen::Index r = 0; k > 0 && r + k <= z.size(); r += k)
    S += z.segment(r, k) * z.segment(r, k).transpose();
  if (k > 0) S /= static_cast<double>(set.size());
  // A ridge of 1e-9 of the mean variance keeps a degenerate observable (a set whose residuals
  // vanish in one component) from blowing the whitening up.
  const double ridge = k > 0 ? 1e-9 * std::max(S.trace() / static_cast<double>(k), 1e-300) : 0.0;
  S += ridge * Eigen::MatrixXd::Identity(k, k);
  d.whiten = Eigen::LLT<Eigen::MatrixXd>(S).matrixL().solve(Eigen::MatrixXd::Identity(k, k));
  whiten_blocks(z, d.whiten);

  const auto& p0 = base.insample_predictions;
  const std::vector<ParameterProbe> probes = probe_calibrated(warm, shape, set, o);
  d.X.resize(static_cast<Eigen::Index>(d.rows.size()), static_cast<Eigen::Index>(probes.size()));
  for (std::size_t c = 0; c < probes.size(); ++c)
    d.X.col(static_cast<Eigen::Index>(c)) =
        scaled_change(probes[c].predictions, p0, set, d.rows, probes[c].step, d.whiten, o);
  // Nuisance directions (IdentifiedBy::kContactFeatures): a fixed parameter moved by half its
  // value, towards the inside of its bounds; only on velocities, since a set with penetration or
  // contact duration does identify the stiffness.
  const bool velocities_only = !base.use[kObsPenetration] && !base.use[kObsDuration];
  for (std::size_t j = 0; velocities_only && j < warm.parameter_count(); ++j) {
    if (warm.spec(j).identified_by != IdentifiedBy::kContactFeatures) continue;
    if (warm.calibrated(j)) continue;  // already a column
    std::vector<double> params = warm.values();
    double step = 0.5 * params[j];
    if (params[j] + step > warm.upper(j)) step = -step / 1.5;
    if (step == 0) continue;
    const double relative = step / params[j];  // per unit relative change: a column of O(1)
    params[j] += step;
    const auto p = predict_observables(warm, shape, params, set, o);
    d.X.conservativeResize(Eigen::NoChange, d.X.cols() + 1);
    d.X.col(d.X.cols() - 1) = scaled_change(p, p0, set, d.rows, relative, d.whiten, o);
  }
  const Eigen::Index N = d.X.rows();
  d.proj = Eigen::MatrixXd::Identity(N, N);
  if (d.X.cols() > 0) {
    // Pseudo-inverse through a complete orthogonal decomposition: collinear directions (a
    // parameter that does nothing at the optimum) are harmless.
    const Eigen::MatrixXd pinv = d.X.completeOrthogonalDecomposition().pseudoInverse();
    d.proj -= d.X * pinv;
  }
  d.z = d.proj * z;
  return d;
}

Score score_of(const Directions& dirs, const Model& cand, const Shape& shape, const ImpactSet& set,
               const std::vector<std::size_t>& added, const AssessOptions& o, double probe_fraction,
               std::size_t hypothesis) {
  Score out;
  if (dirs.z.norm() == 0) return out;
  const auto p0 = predict_observables(cand, shape, cand.values(), set, o);
  for (std::size_t j : added) {
    std::vector<double> params = cand.values();
    const bool at_lower = params[j] <= cand.lower(j), at_upper = params[j] >= cand.upper(j);
    const double toward = at_lower ? cand.upper(j) : at_upper ? cand.lower(j) : cand.upper(j);
    const double step = probe_fraction * (toward - params[j]);
    if (step == 0) continue;
    params[j] += step;
    FiniteChange change = finite_change(dirs, cand, shape, set, params, p0, o, step);
    const Eigen::VectorXd s = change.s;
    if (s.norm() == 0) continue;
    out.directions.push_back(ScoreDirection{j, s, std::move(change.raw),
                                            at_lower   ? 1
                                            : at_upper ? -1
                                                       : 0});
    // Sign convention: positive when moving the parameter from neutral into its bounds moves
    // the predictions towards the measurements (the change is per unit step, so a negative
    // step flips it).
    const double sign = step > 0 ? 1.0 : -1.0;
    const double r = dirs.z.dot(s) / (dirs.z.norm() * s.norm()) * sign;
    if (!(std::fabs(r) <= std::fabs(out.r))) out.r = r;
    stats::ScoreColumn col{hypothesis, per_release_products(dirs, s, dirs.z, set.size()),
                           /*two_sided=*/!at_lower && !at_upper};
    for (double& u : col.u) u *= sign;
    out.columns.push_back(std::move(col));
  }
  return out;
}

FiniteChange finite_change(const Directions& dirs, const Model& cand, const Shape& shape,
                           const ImpactSet& set, const std::vector<double>& params,
                           const std::vector<ObsPrediction>& p0, const AssessOptions& o,
                           double step) {
  const auto p = predict_observables(cand, shape, params, set, o);
  FiniteChange c{Eigen::VectorXd(static_cast<Eigen::Index>(dirs.rows.size())),
                 dirs.proj * scaled_change(p, p0, set, dirs.rows, step, dirs.whiten, o)};
  for (std::size_t row = 0; row < dirs.rows.size(); ++row) {
    const auto [i, k] = dirs.rows[row];
    const double x = (p[i].value[k] - p0[i].value[k]) / step;
    c.raw[static_cast<Eigen::Index>(row)] = std::isfinite(x) ? x : 0.0;
  }
  return c;
}

std::vector<double> per_release_products(const Directions& dirs, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd& y, std::size_t releases) {
  std::vector<double> out(releases, 0.0);
  for (std::size_t row = 0; row < dirs.rows.size(); ++row) {
    const auto e = static_cast<Eigen::Index>(row);
    out[dirs.rows[row].first] += x[e] * y[e];
  }
  return out;
}

Obs rms_per_observable(const Directions& dirs, const Eigen::VectorXd& change,
                       const std::array<bool, kObservables>& use) {
  Obs sum{}, cnt{}, out{};
  for (std::size_t r = 0; r < dirs.rows.size(); ++r) {
    const auto k = static_cast<std::size_t>(dirs.rows[r].second);
    const double x = change[static_cast<Eigen::Index>(r)];
    sum[k] += x * x;
    cnt[k] += 1;
  }
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = use[k] && cnt[k] > 0 ? std::sqrt(sum[k] / cnt[k]) : NAN;
  return out;
}

const EffectRegistry& registry_of(const DiagnoseOptions& o) {
  return o.registry ? *o.registry : EffectRegistry::global();
}

std::string law_of(const Model& model, std::span<const double> values,
                   const std::vector<std::string>& effects, const EffectRegistry& registry) {
  std::string out;
  for (const auto& name : effects) {
    const Effect& e = registry.get(name);
    std::vector<double> v;
    for (const auto& p : e.parameters()) v.push_back(values[model.index(p.name)]);
    out += (out.empty() ? "" : "; ") + e.law(v);
  }
  return out;
}

bool left_neutral(const Model& model, std::span<const double> values,
                  const std::vector<std::string>& effects, const EffectRegistry& registry) {
  bool any = false;
  for (const auto& name : effects)
    for (const auto& p : registry.get(name).parameters()) {
      if (std::isnan(p.neutral)) continue;
      any = true;
      if (values[model.index(p.name)] != p.neutral) return false;
    }
  return any;
}

std::string meaning_of(const Effect& effect) {
  const Signature s = effect.signature();
  return s.meaning.empty() ? std::string(effect.summary()) : std::string(s.meaning);
}

std::vector<std::string> signature_matches(const Effect& effect, const Model& base,
                                           const Baseline& b) {
  std::vector<std::string> out;
  const auto cite = [&](const std::vector<Trend>& pool, const std::string& quantity,
                        ImpactFeature feature) {
    const Trend* t = find_trend(pool, quantity, std::string(feature_name(feature)));
    if (t && t->significant) out.push_back(describe(*t));
  };
  for (const SignatureTrend& st : effect.signature().trends) {
    const ExpectedTrend e = parse_trend(st);  // the registry refused any other word
    if (e.quantity != TrendQuantity::kParameter) {
      cite(b.residual_trends, std::string(quantity_name(e.quantity)), e.feature);
      continue;
    }
    // "param <role>": the base model's parameters of that role (their per-release trends exist
    // for the calibrated ones only).
    for (std::size_t j = 0; j < base.parameter_count(); ++j)
      if (base.spec(j).role == e.parameter)
        cite(b.parameter_trends, parameter_quantity(std::string(base.spec(j).name)), e.feature);
  }
  return out;
}

}  // namespace ricochet::diagnosis::detail
