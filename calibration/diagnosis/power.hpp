// Power of the diagnosis for every family of laws (issue 31, item 2): the weakest law of each
// family that this set would detect with 80 % power. Internal to the diagnosis module (the
// result type, Detectable, is in diagnose.hpp).
//
// The score test of a candidate parameter (signature.hpp) sums per-release contributions
// u_i = s_i . z_i (s its whitened, projected direction per unit of the parameter, z the whitened
// residual). With the law present at a change beta from neutral the residual gains beta s, so
// the score's mean is beta |s|^2 while its standard error, estimated from the set's own
// contributions, is sigma_S = sqrt(n sum_i (u_i - mean u)^2 / nu) (the set's noise and
// scatter, whatever they are). The statistic T = S / sigma_S then has mean beta |s|^2 / sigma_S,
// and it exceeds the family-wise critical value c (the max-T null's 1 - alpha/2 quantile: the
// score route's first step, stats::max_null_quantile) with probability 0.8 when
//   beta_80 = (c + z_0.8) sigma_S / |s|^2,     z_0.8 = 0.8416
// (normal approximation of T; Cohen 1988 ch. 12; the noncentrality of a score test, Cox &
// Hinkley 1974 sec. 9.3). The held-out route can only add power, so this is conservative.
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

/// One row per family with at least one testable candidate, in Family order. `names[h]`,
/// `models[h]` (the warm model plus the candidate at neutral; none when it could not be
/// composed) and `scores[h]` are the candidates as diagnose() tested them; `tests` their score
/// tests; `alpha` the diagnosis's family-wise level.
std::vector<Detectable> minimum_detectable(const Directions& dirs,
                                           const std::vector<std::string>& names,
                                           const std::vector<std::optional<Model>>& models,
                                           const std::vector<Score>& scores,
                                           const stats::ScoreTests& tests,
                                           const EffectRegistry& registry,
                                           const std::array<bool, kObservables>& use, double alpha);

}  // namespace ricochet::diagnosis::detail
