// The second stage of the confidence set of laws (issue 31, items 1 and 4): which families' laws,
// each calibrated on the set, another family's law encompasses. Internal to the diagnosis module
// (the result type, FamilyEncompassing, is in diagnose.hpp).
//
// Why a second stage: the first (confidence.hpp) judges every candidate by its score statistic,
// its direction at its neutral value, where the law as it stands is. Two families whose
// directions there are nearly parallel stay together however many releases are thrown, while
// their calibrated laws, at finite strength, may predict apart. Seen in the closed loop
// (docs/detection-benchmark.md): after 40 designed throws a hidden spin-dependent rolling
// resistance left 16 laws of 5 families in the set, where the design's T-criterion separated the
// families' calibrated laws with lambda = 76 (power 1.0).
//
// The test: the J test of Davidson & MacKinnon (1981, Econometrica 49:781) for non-nested
// models, in its linearised, heteroscedasticity-robust form. For laws a and b, each calibrated on
// the set (rivals.hpp, calibrate_rivals_from: the diagnosis's own full-set calibration):
//   e_i = W D_i^-1 (y_i - f_a(x_i))        a's whitened residual of release i,
//   d_i = W D_i^-1 (f_b(x_i) - f_a(x_i))   the whitened move from a's predictions to b's,
//   d'  = (I - P_b) d,  d~ = (I - P_a) d'   over all releases stacked, P_r = G_r (G_r^T G_r)^+
//   G_r^T
//                                          the projection on law r's whitened parameter Jacobian
//                                          (probe_calibrated): what neither b's refit nor a's own
//                                          parameters can absorb,
//   t_ab = sum_i d~_i^T e_i / sqrt(sum_i (d~_i^T e_i)^2),
// W the score test's whitening (Directions::whiten) and D_i the error denominators. t_ab is the
// robust t of delta = 0 in the artificial nesting (1 - delta) f_a + delta f_b, linearised at the
// calibrations. The projection (I - P_b) makes it the JA test (Fisher & McAleer 1981, J.
// Econometrics 16:103: b refitted to a's predictions instead of to the data, here to first
// order): b's calibration has fitted some of the noise, and the plain J test's d would carry that
// noise into the numerator, a positive bias of about one noise variance per parameter of b that
// a does not share, which dominates when the two laws predict alike (in the linear model the
// bias is sigma^2 tr(P_b (I - P_a)) for J, and tr(P_a (I - P_b)(I - P_a)) = 0 for JA). With a
// true, t_ab then tends to N(0, 1): the terms of different releases are independent, whatever the
// ground scatter within a release. A large positive t_ab says that moving towards b explains
// what a leaves.
//
// The rule: law a leaves when some b has t_ab > c and t_ba <= c: b explains what a leaves, and a
// does not explain what b leaves (the decision table of non-nested tests; when both reject,
// neither law is the truth and both stay). c is the one-sided normal quantile at 1 - alpha / P,
// P the ordered pairs of laws of different families: Bonferroni over every such pair, so that
// the chance of any false exclusion, not only the true law's, is at most alpha. The true law alone would need
// only its m - 1 rivals (1 - alpha / (m - 1)); that level was tried first, on the closed loop's
// exploratory seeds (1-5, 37 diagnoses with this stage): it excluded the truth's family 7 times,
// because the truth's forms are not the candidates' (the premise "the true law is among them"
// fails, and the truth's family's best law is an approximation that another family's law can
// partly explain). At the level of every pair it would have excluded it once or twice.
// With b true, t_ab's mean is about |(I - P_b) (f_b - f^_a)|, the part of the design's lack of
// fit (discrimination.hpp, lambda with b true and a refitted) that b's own parameters cannot
// mimic: what `ricochet design` plans for is what this test sees.
// The JA move alone is blind where a is (nearly) nested in b: when b's best law is a's plus a
// small effect, b refitted to a's predictions IS a, (I - P_b) d vanishes, and the test of a in
// b's direction then has no power however far a misses (seen in the closed loop's exploratory
// seeds: the truth's rolling law at t = 2.9 against every near-neutral rival, c = 3.02, while
// its own score statistic was 4.8). So the direction of b is the comprehensive one (Mizon &
// Richard 1986, Econometrica 54:657, the encompassing principle; the artificial regression of
// a's residual on what b has and a has not): the columns Z = (I - P_a) [ d', G_b,own ], G_b,own
// the whitened Jacobian columns of b's own effect parameters (those the base model does not
// have), and the statistic is the cluster-robust Wald s^T V^+ s, s = sum_i Z_i^T e_i,
// V = sum_i (Z_i^T e_i)(Z_i^T e_i)^T, chi^2 with rank(V) degrees of freedom under a true,
// reported as the one-sided normal score of its tail probability (so that one critical value c
// serves every pair). A column carries nothing when the non-nested move is below 0.1 whitened
// noise variances over the whole set, or when a's own parameters span the effect column; with
// the JA move alone left, t_ab is the signed JA t above.
// What it does not guarantee: when no candidate has the truth's exact form, each family's best
// law is an approximation, and the true family's law can be rejected by another family's (then
// the other is usually rejected too, and both stay).
//
// The laws: each family's kFamilyRepresentatives best first-stage members (largest score
// statistics), and a family leaves only when every one of its laws is excluded by a law of
// another family: when no candidate has the truth's form the family's best member by the local
// score can be an approximation that another family's law explains, while a second member
// (another variable) is not (the closed loop's depth-hardening friction: its family lost in 5 of
// 10 loops with one representative, docs/detection-benchmark.md). Laws of one family are not
// tested against each other, and c counts only the ordered pairs of different families. `none`
// is nested in every law and the first stage decides it; a pair stays or leaves with its first
// effect's family.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "diagnosis/diagnose.hpp"

namespace ricochet::diagnosis::detail {

/// Laws per family in the second stage (file comment).
inline constexpr std::size_t kFamilyRepresentatives = 2;

/// The second stage (file comment) at level `alpha` between `laws` (registered effects, one
/// per family, of the families `families`), each added to `warm` (the base model with its
/// values calibrated on `set`, `base_fit` that calibration) and calibrated on `set`. `whiten`:
/// Directions::whiten; `use`: the set's observables; `options` resolved on `set`.
FamilyEncompassing encompassing_tests(
    const Model& warm, const fit::PopulationFit& base_fit, const Shape& shape, const ImpactSet& set,
    const std::vector<std::string>& laws, const std::vector<Family>& families,
    const Eigen::MatrixXd& whiten, const std::array<bool, kObservables>& use,
    const AssessOptions& options, double alpha, const EffectRegistry& registry);

}  // namespace ricochet::diagnosis::detail
