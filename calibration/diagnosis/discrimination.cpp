// T-optimal discrimination: criterion, power and max-min selection (discrimination.hpp).
#include "diagnosis/discrimination.hpp"

#include <openturns/OT.hxx>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ricochet::diagnosis {

StateTerms state_terms(const Eigen::VectorXd& r, const Eigen::MatrixXd& G) {
  if (G.cols() > kMaxRivalParameters)
    throw std::invalid_argument("state_terms: more than " + std::to_string(kMaxRivalParameters) +
                                " calibrated parameters in a rival");
  StateTerms t;
  t.c = r.squaredNorm();
  t.g = G.transpose() * r;
  t.h = G.transpose() * G;
  return t;
}

TermSum::TermSum(int parameters)
    : g(ParamVector::Zero(parameters)), h(ParamMatrix::Zero(parameters, parameters)) {}

void TermSum::add(const StateTerms& t, double weight) {
  c += weight * t.c;
  g += weight * t.g;
  h += weight * t.h;
}

double TermSum::lambda() const {
  if (g.size() == 0) return std::max(0.0, c);
  // H^+ on the non-null eigenvectors through a ridge of 1e-10 of H's mean eigenvalue: a null
  // direction then contributes (g.v)^2 / ridge with g.v = 0 up to rounding (g lies in H's range:
  // both are sums over the same G_s), and every other direction is solved to 1e-10.
  const double ridge = 1e-10 * std::max(h.trace() / static_cast<double>(h.rows()), 1e-300);
  ParamMatrix hr = h;
  hr.diagonal().array() += ridge;
  const Eigen::LDLT<ParamMatrix> ldlt(hr);
  const ParamVector x = ldlt.solve(g);
  return std::max(0.0, c - g.dot(x));
}

double direction_lambda(const Direction& d, std::span<const std::size_t> states) {
  TermSum s(d.parameters);
  for (std::size_t i : states) s.add(d.states.at(i));
  return s.lambda();
}

double discrimination_power(double lambda, double alpha) {
  if (!(alpha > 0 && alpha < 1))
    throw std::invalid_argument("discrimination_power: alpha must lie in (0, 1)");
  const double z = OT::DistFunc::qNormal(1.0 - alpha / 2.0);
  const double m = std::sqrt(std::max(0.0, lambda));
  // Phi(x) = erfc(-x / sqrt 2) / 2.
  const auto phi = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  return std::min(1.0, phi(m - z) + phi(-m - z));
}

namespace {

constexpr double kMinusInf = -std::numeric_limits<double>::infinity();

// The criterion of the design whose per-direction sums are `sums`, plus candidate `add` (none:
// npos), or a value below `cut` as soon as it is certain that the criterion is below it (the
// pairs are visited in `order`, the weakest first: the minimum falls fastest).
double criterion_with(const std::vector<Direction>& dirs, const std::vector<PairRule>& pairs,
                      const std::vector<TermSum>& sums, const std::vector<std::size_t>& order,
                      std::size_t add, double cut) {
  double m = std::numeric_limits<double>::infinity();
  for (std::size_t p : order) {
    double v = std::numeric_limits<double>::infinity();
    for (std::size_t d : pairs[p].directions) {
      TermSum s = sums[d];
      if (add != static_cast<std::size_t>(-1)) s.add(dirs[d].states[add]);
      v = std::min(v, s.lambda());
    }
    m = std::min(m, v);
    if (m < cut) return m;  // strictly below: a tie is never cut (ties go to the lowest index)
  }
  return m;
}

// Pairs ordered by their value on `sums`, weakest first (stable: ties keep the pair order).
std::vector<std::size_t> weakest_first(const std::vector<PairRule>& pairs,
                                       const std::vector<TermSum>& sums) {
  std::vector<double> v(pairs.size(), std::numeric_limits<double>::infinity());
  for (std::size_t p = 0; p < pairs.size(); ++p)
    for (std::size_t d : pairs[p].directions) v[p] = std::min(v[p], sums[d].lambda());
  std::vector<std::size_t> order(pairs.size());
  for (std::size_t p = 0; p < order.size(); ++p) order[p] = p;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  return order;
}

// The best candidate to add to `sums` (not in `taken`): the largest criterion, the lowest index
// among equals. Serial: one evaluation is a few small solves (well under a microsecond), and a
// parallel region per step cost more than it saved (N = 40 on the lab cylinders: 0.13 s on one
// thread, 0.5-3.7 s on two, with other jobs on the machine). A candidate is cut as soon as its
// criterion is certainly below the best so far; a tie is never cut.
std::pair<std::size_t, double> best_addition(const std::vector<Direction>& dirs,
                                             const std::vector<PairRule>& pairs,
                                             const std::vector<TermSum>& sums,
                                             const std::vector<char>& taken, std::size_t fixed,
                                             std::size_t candidates) {
  const std::vector<std::size_t> order = weakest_first(pairs, sums);
  std::size_t arg = static_cast<std::size_t>(-1);
  double best = kMinusInf;
  for (std::size_t k = 0; k < candidates; ++k) {
    if (taken[k]) continue;
    const double v = criterion_with(dirs, pairs, sums, order, fixed + k, best);
    if (arg == static_cast<std::size_t>(-1) || v > best) arg = k, best = v;
  }
  return {arg, best};
}

std::vector<TermSum> sums_of(const std::vector<Direction>& dirs, std::size_t fixed,
                             const std::vector<std::size_t>& chosen, std::size_t skip) {
  std::vector<TermSum> sums;
  for (const Direction& d : dirs) {
    TermSum s(d.parameters);
    for (std::size_t i = 0; i < fixed; ++i) s.add(d.states[i]);
    for (std::size_t j = 0; j < chosen.size(); ++j)
      if (j != skip) s.add(d.states[chosen[j]]);
    sums.push_back(std::move(s));
  }
  return sums;
}

}  // namespace

Selection select_max_min(const std::vector<Direction>& dirs, const std::vector<PairRule>& pairs,
                         std::size_t fixed, std::size_t candidates,
                         const SelectionOptions& options) {
  if (options.budget > candidates)
    throw std::invalid_argument("select_max_min: budget above the number of candidates");
  for (const Direction& d : dirs)
    if (d.states.size() < fixed + candidates)
      throw std::invalid_argument("select_max_min: a direction lacks terms for some states");
  Selection sel;
  std::vector<char> taken(candidates, 0);
  const std::size_t none = static_cast<std::size_t>(-1);
  // Greedy forward selection.
  std::vector<TermSum> sums = sums_of(dirs, fixed, {}, none);
  for (std::size_t step = 0; step < options.budget; ++step) {
    const auto [k, v] = best_addition(dirs, pairs, sums, taken, fixed, candidates);
    taken[k] = 1;
    sel.chosen.push_back(fixed + k);
    for (std::size_t d = 0; d < dirs.size(); ++d) sums[d].add(dirs[d].states[fixed + k]);
  }
  const auto value_of = [&](const std::vector<TermSum>& s) {
    return criterion_with(dirs, pairs, s, weakest_first(pairs, s), none, kMinusInf);
  };
  sel.greedy_value = sel.value = pairs.empty() ? 0.0 : value_of(sums);
  if (pairs.empty()) return sel;
  // Exchange passes: for each chosen state in turn, the best replacement among the candidates
  // not chosen (the state itself competing as "keep"), taken when it raises the criterion.
  for (sel.passes = 0; sel.passes < options.max_passes;) {
    ++sel.passes;
    bool improved = false;
    for (std::size_t j = 0; j < sel.chosen.size(); ++j) {
      const std::vector<TermSum> without = sums_of(dirs, fixed, sel.chosen, j);
      const auto [k, v] = best_addition(dirs, pairs, without, taken, fixed, candidates);
      if (k == none || !(v > sel.value + options.relative_gain * std::fabs(sel.value))) continue;
      taken[sel.chosen[j] - fixed] = 0;
      taken[k] = 1;
      sel.chosen[j] = fixed + k;
      sel.value = v;
      ++sel.swaps;
      improved = true;
    }
    if (!improved) break;
  }
  return sel;
}

}  // namespace ricochet::diagnosis
