#include "stats/stats.hpp"

#include <openturns/OT.hxx>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "common/nan.hpp"

namespace ricochet::stats {
namespace {

std::vector<double> finite_values(std::span<const double> x) {
  std::vector<double> out;
  out.reserve(x.size());
  for (double v : x)
    if (!std::isnan(v)) out.push_back(v);
  return out;
}

}  // namespace

Summary summarize(std::span<const double> x) {
  const std::vector<double> v = finite_values(x);
  Summary s;
  s.n = v.size();
  if (v.empty()) {
    s.mean = s.std = s.cv = s.min = s.max = kNaN;
    return s;
  }
  // Two passes (mean, then squared deviations): no cancellation for samples with a large mean,
  // such as omega_in around -65 rad/s with a spread of 6 rad/s.
  double sum = 0;
  for (double a : v) sum += a;
  s.mean = sum / static_cast<double>(s.n);
  double ss = 0;
  for (double a : v) ss += (a - s.mean) * (a - s.mean);
  // Sample standard deviation with Bessel's correction (n - 1), as in paper Table 2.
  s.std = s.n > 1 ? std::sqrt(ss / static_cast<double>(s.n - 1)) : kNaN;
  s.cv = s.std / s.mean;
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  s.min = *lo;
  s.max = *hi;
  return s;
}

Ecdf ecdf(std::span<const double> x) {
  Ecdf e;
  e.x = finite_values(x);
  std::sort(e.x.begin(), e.x.end());
  const double n = static_cast<double>(e.x.size());
  e.p.resize(e.x.size());
  for (std::size_t i = 0; i < e.x.size(); ++i) e.p[i] = static_cast<double>(i + 1) / n;
  return e;
}

KsResult ks_two_sample(std::span<const double> a, std::span<const double> b) {
  std::vector<double> va = finite_values(a);
  std::vector<double> vb = finite_values(b);
  if (va.empty() || vb.empty())
    throw std::invalid_argument("two-sample Kolmogorov-Smirnov test needs two non-empty samples");
  // D = sup |F_a - F_b| by a merge of the sorted samples, O(n log n). OT's own
  // HypothesisTest::TwoSamplesKolmogorov computes the same D in O((n_a + n_b)^2) (3.8 s for
  // 28 against 50,000 values), so only the p-value comes from OpenTURNS, exactly as that
  // function computes it: the Kolmogorov distribution's upper tail at the effective size
  // floor(n_a n_b / (n_a + n_b)) (tests check both against TwoSamplesKolmogorov).
  std::sort(va.begin(), va.end());
  std::sort(vb.begin(), vb.end());
  const double na = static_cast<double>(va.size()), nb = static_cast<double>(vb.size());
  std::size_t i = 0, j = 0;
  double d = 0.0;
  while (i < va.size() && j < vb.size()) {
    const double v = std::min(va[i], vb[j]);
    while (i < va.size() && va[i] <= v) ++i;
    while (j < vb.size() && vb[j] <= v) ++j;
    d = std::max(d, std::fabs(static_cast<double>(i) / na - static_cast<double>(j) / nb));
  }
  const auto effective = static_cast<OT::UnsignedInteger>(na * nb / (na + nb));
  return {d, OT::DistFunc::pKolmogorov(std::max<OT::UnsignedInteger>(effective, 1), d, true)};
}

NoisyKsResult ks_with_measurement_noise(std::span<const double> model,
                                        std::span<const double> measured, double sigma,
                                        std::size_t draws, std::uint64_t seed) {
  if (!(sigma >= 0.0) || !std::isfinite(sigma))
    throw std::invalid_argument("measurement noise sigma must be finite and >= 0");
  if (draws == 0) throw std::invalid_argument("measurement-noise KS needs at least one draw");
  const std::vector<double> exact = finite_values(model);
  if (exact.empty()) throw std::invalid_argument("measurement-noise KS: empty model sample");
  std::mt19937_64 rng(seed);
  // Box-Muller on 53-bit uniforms: std::normal_distribution's algorithm is the library's choice.
  const auto uniform = [&] { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; };
  std::vector<double> p(draws), noisy(exact.size());
  for (std::size_t d = 0; d < draws; ++d) {
    for (std::size_t i = 0; i < exact.size(); ++i) {
      const double z = std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * M_PI * uniform());
      noisy[i] = exact[i] + sigma * z;
    }
    p[d] = ks_two_sample(noisy, measured).p_value;
  }
  NoisyKsResult r;
  r.sigma = sigma;
  r.draws = draws;
  r.share_p_above_005 =
      static_cast<double>(std::count_if(p.begin(), p.end(), [](double v) { return v > 0.05; })) /
      static_cast<double>(draws);
  std::sort(p.begin(), p.end());
  // Order statistics (lower median; the 10th percentile by the nearest rank).
  r.median_p = p[(draws - 1) / 2];
  r.p10 = p[static_cast<std::size_t>(std::ceil(0.1 * static_cast<double>(draws))) - 1];
  return r;
}

Correlation pearson(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size())
    throw std::invalid_argument("pearson: the two samples have different sizes");
  std::vector<double> vx, vy;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::isnan(x[i]) || std::isnan(y[i])) continue;
    vx.push_back(x[i]);
    vy.push_back(y[i]);
  }
  Correlation c;
  c.n = vx.size();
  // OpenTURNS refuses fewer than 3 pairs (the t statistic has n - 2 degrees of freedom), and a
  // constant sample has no correlation coefficient.
  const Summary sx = summarize(vx);
  const Summary sy = summarize(vy);
  if (c.n < 3 || !(sx.std > 0) || !(sy.std > 0)) {
    c.r = kNaN;
    c.p_value = kNaN;
    return c;
  }
  OT::Sample joint(c.n, 2);
  for (std::size_t i = 0; i < c.n; ++i) {
    joint(i, 0) = vx[i];
    joint(i, 1) = vy[i];
  }
  c.r = joint.computePearsonCorrelation()(0, 1);
  // Two-sided p-value of H0: rho = 0, t = r sqrt((n-2)/(1-r^2)) ~ Student(n - 2).
  c.p_value = OT::HypothesisTest::Pearson(joint.getMarginal(0), joint.getMarginal(1)).getPValue();
  return c;
}

double student_t_upper_tail(double t, double dof) {
  if (!(dof > 0)) throw std::invalid_argument("student_t_upper_tail: dof must be positive");
  if (std::isnan(t)) return kNaN;
  return OT::DistFunc::pStudent(dof, t, /*tail=*/true);
}

double chi_square_upper_tail(double x, double dof) {
  if (!(dof > 0)) throw std::invalid_argument("chi_square_upper_tail: dof must be positive");
  if (!(x > 0)) return 1.0;
  // chi^2_k = Gamma(k/2, scale 2): P(X > x) = Q(k/2, x/2).
  return OT::DistFunc::pGamma(0.5 * dof, 0.5 * x, /*tail=*/true);
}

std::vector<double> holm_adjust(std::span<const double> p, std::size_t family_size) {
  const std::size_t m = std::max(family_size, p.size());
  std::vector<std::size_t> order(p.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto value = [&](std::size_t i) { return std::isnan(p[i]) ? 1.0 : p[i]; };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return value(a) < value(b); });
  std::vector<double> out(p.size(), kNaN);
  double running = 0.0;
  for (std::size_t r = 0; r < order.size(); ++r) {
    const std::size_t i = order[r];
    // Step-down: the r-th smallest p is multiplied by (m - r); adjusted values are monotone.
    running = std::max(running, std::min(1.0, static_cast<double>(m - r) * value(i)));
    out[i] = std::isnan(p[i]) ? kNaN : running;
  }
  return out;
}

ResampledTest corrected_resampled_t(std::span<const double> d, double n_test, double n_train) {
  ResampledTest r;
  r.splits = d.size();
  if (d.empty()) return r;
  for (double x : d) r.mean += x / static_cast<double>(d.size());
  if (d.size() < 2 || !(n_train > 0)) {
    r.se = kNaN, r.t = kNaN, r.p_value = kNaN;
    return r;
  }
  double s2 = 0;
  for (double x : d) s2 += (x - r.mean) * (x - r.mean);
  s2 /= static_cast<double>(d.size() - 1);
  const double J = static_cast<double>(d.size());
  r.se = std::sqrt((1.0 / J + n_test / n_train) * s2);
  if (r.se > 0) {
    r.t = r.mean / r.se;
    r.p_value = student_t_upper_tail(r.t, J - 1.0);
  } else {
    // Identical differences on every split: certain when positive, impossible otherwise.
    r.t = r.mean > 0 ? INFINITY : r.mean < 0 ? -INFINITY : 0.0;
    r.p_value = r.mean > 0 ? 0.0 : 1.0;
  }
  return r;
}

Proportion wilson(std::size_t successes, std::size_t n, double alpha) {
  Proportion w;
  if (n == 0) return w;
  const double z = OT::DistFunc::qNormal(1.0 - alpha / 2.0);
  const double nn = static_cast<double>(n);
  const double ph = static_cast<double>(successes) / nn;
  const double denom = 1.0 + z * z / nn;
  const double centre = (ph + z * z / (2.0 * nn)) / denom;
  const double half = z * std::sqrt(ph * (1.0 - ph) / nn + z * z / (4.0 * nn * nn)) / denom;
  w.rate = ph;
  w.lo = std::max(0.0, centre - half);
  w.hi = std::min(1.0, centre + half);
  return w;
}

Proportion clopper_pearson(std::size_t successes, std::size_t n, double alpha) {
  Proportion p;
  if (n == 0) return p;
  const double k = static_cast<double>(successes), nn = static_cast<double>(n);
  p.rate = k / nn;
  p.lo = successes == 0 ? 0.0 : OT::DistFunc::qBeta(k, nn - k + 1.0, alpha / 2.0);
  p.hi = successes == n ? 1.0 : OT::DistFunc::qBeta(k + 1.0, nn - k, 1.0 - alpha / 2.0);
  return p;
}

}  // namespace ricochet::stats
