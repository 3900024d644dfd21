// The second stage of the confidence set of laws (encompassing.hpp).
#include "diagnosis/encompassing.hpp"
#include "common/nan.hpp"

#include <openturns/OT.hxx>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "common/clock.hpp"
#include "diagnosis/rivals.hpp"

namespace ricochet::diagnosis::detail {
namespace {

// The smallest non-nested move that counts, |(I - P_a)(I - P_b) d|^2 in whitened units summed
// over the set: below it the move would carry less than a third of one noise standard deviation.
constexpr double kMinMove = 0.1;

// One law on the set's releases, whitened and stacked (release-major, the used observables of
// a release contiguous): its predictions f, its residual e = W D^-1 (y - f), and G, the columns
// of its calibrated parameters' forward differences.
struct Stacked {
  Eigen::VectorXd f, e;
  Eigen::MatrixXd G;
  std::vector<Eigen::Index> own;  ///< the columns of G of the law's own effect (not the base's)
  std::vector<char> ok;           ///< per release: it rebounds under the law and its probes
};

Stacked stack(const Rival& r, const Model& base, const Shape& shape, const ImpactSet& set,
              const Eigen::MatrixXd& W, const std::array<bool, kObservables>& use,
              const AssessOptions& o) {
  std::vector<int> obs;
  for (int k = 0; k < kObservables; ++k)
    if (use[k]) obs.push_back(k);
  const auto K = static_cast<Eigen::Index>(obs.size());
  const auto N = static_cast<Eigen::Index>(set.size()) * K;
  const std::vector<ObsPrediction> p =
      predict_observables(r.model, shape, r.model.values(), set, o);
  const std::vector<ParameterProbe> probes = probe_calibrated(r.model, shape, set, o);
  const ErrorReport rep = error_report(set, p, use, o);
  Stacked s;
  s.f.resize(N);
  s.e.resize(N);
  s.G.resize(N, static_cast<Eigen::Index>(probes.size()));
  s.ok.assign(set.size(), 0);
  for (std::size_t i = 0; i < set.size(); ++i) {
    const Obs D = error_scale(set.impacts[i], o);
    const Eigen::Index row0 = static_cast<Eigen::Index>(i) * K;
    Eigen::VectorXd f(K), e(K);
    Eigen::MatrixXd g(K, s.G.cols());
    bool ok = p[i].status == CollisionStatus::kOk;
    for (Eigen::Index a = 0; a < K; ++a) {
      const int k = obs[static_cast<std::size_t>(a)];
      f[a] = p[i].value[k] / D[k];
      e[a] = rep.residual[i][k] / D[k];
      for (std::size_t c = 0; c < probes.size(); ++c) {
        const ObsPrediction& q = probes[c].predictions[i];
        ok = ok && q.status == CollisionStatus::kOk;
        g(a, static_cast<Eigen::Index>(c)) = (q.value[k] - p[i].value[k]) / probes[c].step / D[k];
      }
    }
    s.ok[i] = ok && f.allFinite() && e.allFinite() && g.allFinite();
    s.f.segment(row0, K) = s.ok[i] ? Eigen::VectorXd(W * f) : Eigen::VectorXd::Zero(K);
    s.e.segment(row0, K) = s.ok[i] ? Eigen::VectorXd(W * e) : Eigen::VectorXd::Zero(K);
    s.G.middleRows(row0, K) = s.ok[i] ? Eigen::MatrixXd(W * g) : Eigen::MatrixXd::Zero(K, g.cols());
  }
  const std::vector<std::string> shared = base.parameter_names();
  for (std::size_t c = 0; c < probes.size(); ++c)
    if (std::find(shared.begin(), shared.end(), r.model.spec(probes[c].index).name) == shared.end())
      s.own.push_back(static_cast<Eigen::Index>(c));
  return s;
}

// Keeps the releases every law predicts (a triangle can stay in the sand under one law's probe):
// the others' rows are zeroed, so they count in no sum and no projection.
void keep_common(std::vector<Stacked>& laws, Eigen::Index K) {
  if (laws.empty()) return;
  std::vector<char> all(laws.front().ok.size(), 1);
  for (const Stacked& s : laws)
    for (std::size_t i = 0; i < all.size() && i < s.ok.size(); ++i) all[i] = all[i] && s.ok[i];
  for (Stacked& s : laws)
    for (std::size_t i = 0; i < all.size(); ++i)
      if (!all[i]) {
        const Eigen::Index r = static_cast<Eigen::Index>(i) * K;
        s.f.segment(r, K).setZero();
        s.e.segment(r, K).setZero();
        s.G.middleRows(r, K).setZero();
      }
}

// d -= G (G^T G)^+ G^T d.
void project_out(Eigen::VectorXd& d, const Eigen::MatrixXd& G) {
  if (G.cols() > 0) d -= G * G.completeOrthogonalDecomposition().solve(d);
}

// The statistic of the file comment, law a true, in the direction of law b, as a one-sided
// normal score (the chi^2_q tail probability mapped to N(0, 1)).
double encompassing_statistic(const Stacked& a, const Stacked& b, Eigen::Index K) {
  Eigen::VectorXd d = b.f - a.f;
  project_out(d, b.G);  // the JA form: what b's own refit cannot take up (file comment)
  const auto own = static_cast<Eigen::Index>(b.own.size());
  Eigen::MatrixXd Z(d.size(), 1 + own);
  Z.col(0) = d;
  for (Eigen::Index c = 0; c < own; ++c) Z.col(1 + c) = b.G.col(b.own[static_cast<std::size_t>(c)]);
  for (Eigen::Index c = 0; c < Z.cols(); ++c) {
    Eigen::VectorXd z = Z.col(c);
    project_out(z, a.G);
    Z.col(c) = z;
  }
  // Directions that carry nothing: the non-nested move when it is below kMinMove noise units
  // over the whole set (the laws predict alike once refitted), an effect column a's own
  // parameters span.
  std::vector<Eigen::Index> keep;
  if (Z.col(0).squaredNorm() >= kMinMove) keep.push_back(0);
  for (Eigen::Index c = 1; c < Z.cols(); ++c)
    if (Z.col(c).norm() > 1e-8 * b.G.col(b.own[static_cast<std::size_t>(c - 1)]).norm())
      keep.push_back(c);
  if (keep.empty()) return kNaN;
  // Per release, the score contributions u_i = Z_i^T e_i; robust (cluster) Wald s^T V^+ s.
  const auto q = static_cast<Eigen::Index>(keep.size());
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(q);
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(q, q);
  for (Eigen::Index r = 0; r + K <= d.size(); r += K) {
    Eigen::VectorXd u(q);
    for (Eigen::Index j = 0; j < q; ++j)
      u[j] = Z.col(keep[static_cast<std::size_t>(j)]).segment(r, K).dot(a.e.segment(r, K));
    sum += u;
    V += u * u.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(V);
  const double top = eig.eigenvalues().maxCoeff();
  if (!(top > 0)) return kNaN;
  double wald = 0;
  int rank = 0;
  for (Eigen::Index j = 0; j < q; ++j) {
    const double lj = eig.eigenvalues()[j];
    if (lj <= 1e-10 * top) continue;
    const double p = eig.eigenvectors().col(j).dot(sum);
    wald += p * p / lj;
    ++rank;
  }
  // One degree of freedom keeps the sign of the non-nested move (the JA t itself).
  if (q == 1 && keep.front() == 0) return sum[0] / std::sqrt(V(0, 0));
  const double upper = OT::DistFunc::pGamma(0.5 * rank, 0.5 * wald, true);  // P(chi^2 > wald)
  return upper > 0 ? OT::DistFunc::qNormal(upper, true) : 40.0;
}

}  // namespace

FamilyEncompassing encompassing_tests(
    const Model& warm, const fit::PopulationFit& base_fit, const Shape& shape, const ImpactSet& set,
    const std::vector<std::string>& laws, const std::vector<Family>& families,
    const Eigen::MatrixXd& whiten, const std::array<bool, kObservables>& use,
    const AssessOptions& options, double alpha, const EffectRegistry& registry) {
  const auto t0 = std::chrono::steady_clock::now();
  const AssessOptions o = resolve_scale(set, options);
  const std::size_t m = laws.size();
  FamilyEncompassing out;
  out.alpha = alpha;
  out.laws = laws;
  out.families = families;
  out.calibrated.assign(m, std::string());
  out.t.assign(m, std::vector<double>(m, kNaN));
  out.excluded_by.assign(m, -1);
  if (m < 2) return out;
  // Bonferroni over the ordered pairs of laws of different families (the tests that can exclude).
  std::size_t pairs = 0;
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = 0; b < m; ++b) pairs += families[a] != families[b];
  if (pairs == 0) return out;
  out.critical = OT::DistFunc::qNormal(1.0 - alpha / static_cast<double>(pairs));

  Rival base;
  base.name = "none";
  base.model = warm;
  base.fit = base_fit;
  std::vector<std::vector<std::string>> effects;
  for (const auto& l : laws) effects.push_back({l});
  // A law that cannot be calibrated here is not judged (it stays); the others still are.
  const std::vector<RivalCalibration> rivals =
      try_calibrate_rivals_from(base, shape, set, effects, o, registry);
  const Eigen::Index K = whiten.rows();
  std::vector<Stacked> s;
  std::vector<std::size_t> judged;  // the calibrated laws
  for (std::size_t k = 0; k < m; ++k)
    if (const auto& r = rivals[k].rival) {
      out.calibrated[k] = r->law;
      s.push_back(stack(*r, warm, shape, set, whiten, use, o));
      judged.push_back(k);
    }
  keep_common(s, K);
  for (std::size_t x = 0; x < judged.size(); ++x)
    for (std::size_t y = 0; y < judged.size(); ++y)
      if (x != y) out.t[judged[x]][judged[y]] = encompassing_statistic(s[x], s[y], K);
  const double c = out.critical;
  for (std::size_t a = 0; a < m; ++a) {
    double worst = -std::numeric_limits<double>::infinity();
    for (std::size_t b = 0; b < m; ++b) {
      const double tab = out.t[a][b], tba = out.t[b][a];
      if (families[a] == families[b] || !std::isfinite(tab) || !std::isfinite(tba)) continue;
      if (tab > c && tba <= c && tab > worst) {
        worst = tab;
        out.excluded_by[a] = static_cast<int>(b);
      }
    }
  }
  // A family leaves only when every law representing it is excluded: one approximate member's
  // rejection does not carry the family (file comment).
  for (std::size_t a = 0; a < m; ++a)
    if (out.excluded_by[a] >= 0)
      for (std::size_t k = 0; k < m; ++k)
        if (families[k] == families[a] && out.excluded_by[k] < 0) {
          out.excluded_by[a] = -1;
          break;
        }
  // Every law excluded by another (a cycle of rejections): the tests contradict each other
  // and decide nothing.
  if (std::all_of(out.excluded_by.begin(), out.excluded_by.end(), [](int b) { return b >= 0; }))
    out.excluded_by.assign(m, -1);
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace ricochet::diagnosis::detail
