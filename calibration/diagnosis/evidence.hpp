// Words with numbers for the diagnosis: each candidate's evidence, the verdict's summary, and
// what is left unexplained. Internal to the diagnosis module; every number comes from the
// structures of diagnose.hpp, nothing is computed here but text.
#pragma once

#include <string>
#include <vector>

#include "diagnosis/diagnose.hpp"

namespace ricochet::diagnosis::detail {

/// Mean residual of observable k with its t statistic, when |t| >= 3 (a bias, e.g. the contact
/// always too long); empty otherwise.
std::string bias_text(const ErrorReport& r, int k);

/// The evidence of a judged candidate: the drop and its corrected test, the observable whose
/// error falls most, the score test, the calibrated law, the declared signature trends found.
std::string evidence_of(const Candidate& c, const Baseline& b, const DiagnoseOptions& o);

/// The verdict of `d` and its confidence set of laws, in sentences (ranking, verdict, scatter
/// and confidence set already set).
std::string summary_of(const Diagnosis& d, const DiagnoseOptions& o);
/// The verdict alone, one or two sentences.
std::string verdict_text(const Diagnosis& d, const DiagnoseOptions& o);
/// The confidence set in one sentence: how many laws of how many families, by family, and
/// whether the law as it stands is one of them, read with `missing_physics` (the verdict: the
/// law as it stands is above its floor): then no candidate is needed beside it and what it lacks
/// is not among them, else perhaps nothing is missing. Empty when no set was computed.
std::string confidence_text(const LawConfidenceSet& cs, bool missing_physics);
/// The finite components of `v` with their units, "0.28 m/s, 0.35 m/s, 5 rad/s", each to
/// `digits` significant digits.
std::string observables_text(const Obs& v, int digits);
/// The minimum detectable law of each family in one sentence (power.hpp); empty without rows.
std::string detectable_text(const std::vector<Detectable>& rows, std::size_t releases);

/// What a model leaves unexplained: its ratio to the floor, observables far above their floor,
/// one line per residual with a Holm-significant trend, contact biases.
std::vector<std::string> unexplained_after(const Assessment& a, const NoiseFloor& floor,
                                           const Adequacy& q, const std::vector<Feature>& features,
                                           const TrendOptions& to, const std::string& who,
                                           const std::vector<Trend>* given = nullptr);

}  // namespace ricochet::diagnosis::detail
