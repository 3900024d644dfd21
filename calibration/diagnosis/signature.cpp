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

Eigen::VectorXd scaled_change(const std::vector<ObsPrediction>& a,
                              const std::vector<ObsPrediction>& b, const ImpactSet& set,
                              const std::vector<std::pair<std::size_t, int>>& rows, double step,
                              const AssessOptions& o) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto [i, k] = rows[r];
    const double d = error_scale(set.impacts[i], o)[k];
    const double x = (a[i].value[k] - b[i].value[k]) / step / d;
    v[static_cast<Eigen::Index>(r)] = std::isfinite(x) ? x : 0.0;
  }
  return v;
}

}  // namespace

Directions base_directions(const Model& warm, const Shape& shape, const ImpactSet& set,
                           const Assessment& base, const AssessOptions& o) {
  Directions d;
  d.rows = rows_of(set.size(), base.use);
  const auto& p0 = base.insample_predictions;
  const std::vector<std::size_t> cal = warm.calibrated_indices();
  d.X.resize(static_cast<Eigen::Index>(d.rows.size()), static_cast<Eigen::Index>(cal.size()));
  for (std::size_t c = 0; c < cal.size(); ++c) {
    const std::size_t j = cal[c];
    std::vector<double> params = warm.values();
    double step = 0.02 * (warm.upper(j) - warm.lower(j));
    if (params[j] + step > warm.upper(j)) step = -step;
    params[j] += step;
    const auto p = predict_observables(warm, shape, params, set, o);
    d.X.col(static_cast<Eigen::Index>(c)) = scaled_change(p, p0, set, d.rows, step, o);
  }
  const Eigen::Index N = d.X.rows();
  d.proj = Eigen::MatrixXd::Identity(N, N);
  if (d.X.cols() > 0) {
    // Pseudo-inverse through a complete orthogonal decomposition: collinear directions (a
    // parameter that does nothing at the optimum) are harmless.
    const Eigen::MatrixXd pinv = d.X.completeOrthogonalDecomposition().pseudoInverse();
    d.proj -= d.X * pinv;
  }
  Eigen::VectorXd z(N);
  for (std::size_t r = 0; r < d.rows.size(); ++r) {
    const auto [i, k] = d.rows[r];
    const double s = error_scale(set.impacts[i], o)[k];
    z[static_cast<Eigen::Index>(r)] = base.insample.residual[i][k] / s;
  }
  d.z = d.proj * z;
  return d;
}

// The score-test correlation of a candidate (file comment of diagnose.hpp): the largest over its
// calibrated parameters.
double signature_r(const Directions& dirs, const Model& cand, const Shape& shape,
                   const ImpactSet& set, const std::vector<std::size_t>& added,
                   const AssessOptions& o, double probe_fraction) {
  if (dirs.z.norm() == 0) return NAN;
  const auto p0 = predict_observables(cand, shape, cand.values(), set, o);
  double best = NAN;
  for (std::size_t j : added) {
    std::vector<double> params = cand.values();
    const double toward = params[j] <= cand.lower(j)   ? cand.upper(j)
                          : params[j] >= cand.upper(j) ? cand.lower(j)
                                                       : cand.upper(j);
    const double step = probe_fraction * (toward - params[j]);
    if (step == 0) continue;
    params[j] += step;
    const auto p = predict_observables(cand, shape, params, set, o);
    const Eigen::VectorXd s = dirs.proj * scaled_change(p, p0, set, dirs.rows, step, o);
    if (s.norm() == 0) continue;
    // Sign convention: positive when increasing the parameter from neutral moves the
    // predictions towards the measurements.
    const double r = dirs.z.dot(s) / (dirs.z.norm() * s.norm()) * (step > 0 ? 1.0 : -1.0);
    if (!(std::fabs(r) <= std::fabs(best))) best = r;
  }
  return best;
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

std::string meaning_of(const Effect& effect) {
  const Signature s = effect.signature();
  return s.meaning.empty() ? std::string(effect.summary()) : std::string(s.meaning);
}

std::vector<std::string> signature_matches(const Effect& effect, const Baseline& b) {
  std::vector<std::string> out;
  for (const SignatureTrend& st : effect.signature().trends) {
    const std::string q(st.quantity), f(st.feature);
    const std::vector<Trend>& pool =
        q.rfind("param", 0) == 0 ? b.parameter_trends : b.residual_trends;
    if (const Trend* t = find_trend(pool, q, f); t && t->significant) out.push_back(describe(*t));
  }
  return out;
}

}  // namespace ricochet::diagnosis::detail
