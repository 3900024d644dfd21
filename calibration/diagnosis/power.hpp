// Power of the diagnosis for every family of laws (issue 31, item 2): the weakest law of each
// family that this set would detect with 80 % power. Internal to the diagnosis module (the
// result type, Detectable, is in diagnose.hpp).
//
// The score test of a candidate parameter (signature.hpp) sums per-release contributions
// u_i = s_i . z_i (s its whitened, projected direction per unit of the parameter, z the whitened
// residual). With the law present at a change beta from neutral the residual gains beta s, so
// the score's mean is beta |s|^2 while its standard error, estimated from the set's own
// contributions, is sigma_S = sqrt(n sum_i (u_i - mean u)^2 / nu) (the set's noise and
// scatter, whatever they are). With the law present the contributions also spread: release i
// gains beta a_i, a_i = |s_i|^2 over its observables, so the standard error the test itself
// estimates grows to sqrt(sigma_S^2 + beta^2 V), V = n sum_i (a_i - mean a)^2 / nu. The
// statistic T = S / sigma_S then has mean
//   T(beta) = beta A / sqrt(sigma_S^2 + beta^2 V),   A = |s|^2 = sum_i a_i,
// which saturates at the ceiling A / sqrt(V): a law whose change differs from release to release
// as much as it grows is never seen with certainty. T exceeds the family-wise critical value c
// (the max-T null's 1 - alpha/2 quantile: the score route's first step,
// stats::max_null_quantile) with probability 0.8 when T(beta) = c + z_0.8, z_0.8 = 0.8416:
//   beta_80 = (c + z_0.8) sigma_S / sqrt(A^2 - (c + z_0.8)^2 V),
// and at no strength when A^2 <= (c + z_0.8)^2 V (normal approximation of T; Cohen 1988 ch. 12;
// the noncentrality of a score test, Cox & Hinkley 1974 sec. 9.3). Without the spread term
// (beta_80 = (c + z_0.8) sigma_S / A, the first version) the predictions were measured to be
// optimistic: predicted power 0.87-0.95 where the score test rejected in 3-40 % of the sets
// (docs/detection-benchmark.md, "Power calibration").
// At a finite strength: the linear change beta s overstates a law whose effect saturates (an
// inertial drag's F = c_d v^2 at the lab cylinder's mean state: V_out^y falls by 0.10 m/s at
// c_d = 1000 kg/m and by 0.32 m/s, not 0.55, at 5000 kg/m; ricochet simulate), and with it the
// power (the calibration study's drag cells: predicted mean T 2.0-3.9, measured 1.1-1.7). So the
// strength is solved on the engine itself: the law at change beta adds g(beta), its predictions'
// whitened and projected change (finite_change), to the residual; the contributions become
// a_i(beta) = s_i . g_i(beta) (beta a_i to first order), and
//   T(beta) = sum_i a_i(beta) / sqrt(sigma_S^2 + V(beta)),  V(beta) from the a_i(beta) as above,
// solved for T(beta_80) = c + z_0.8 by bracketing from the linear beta_80 and bisection in
// log beta (about 15 engine passes over the set per parameter). The points evaluated are
// reported (Detectable::t_curve), so that the power at any other strength can be read off.
// Still not modelled: the whitening's own growth with the law (the residual covariance
// includes it) and the base parameters' nonlinear refit; the held-out route can only add power.
// Per family the candidate whose law at beta_80 moves the predictions least, in noise units,
// is reported, with its parameter value, its law and its change of the predictions in SI units.
// What it assumes: the local (linear) model around the base fit, and the law's own form; a
// truth of another form of the same family is detected with the power of its projection.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "diagnosis/diagnose.hpp"
#include "diagnosis/signature.hpp"

namespace ricochet::diagnosis::detail {

/// One row per testable parameter of every candidate, in the order of `names`. `names[h]`,
/// `models[h]` (the warm model plus the candidate at neutral; none when it could not be
/// composed) and `scores[h]` are the candidates as diagnose() tested them; `tests` their score
/// tests; `alpha` the diagnosis's family-wise level; `shape`, `set` and `o` (resolved on the
/// set) those of the diagnosis, for the engine runs at finite strengths; `progress` (optional)
/// is advanced once per candidate.
std::vector<Detectable> detectable_candidates(
    const Directions& dirs, const std::vector<std::string>& names,
    const std::vector<std::optional<Model>>& models, const std::vector<Score>& scores,
    const stats::ScoreTests& tests, const EffectRegistry& registry,
    const std::array<bool, kObservables>& use, double alpha, const Shape& shape,
    const ImpactSet& set, const AssessOptions& o, Progress* progress = nullptr);

/// The most detectable row of each family (a law within its bounds first, then the smallest
/// change in noise units), in Family order.
std::vector<Detectable> minimum_detectable(const std::vector<Detectable>& candidates);

}  // namespace ricochet::diagnosis::detail
