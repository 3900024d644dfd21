#include "diagnosis/evidence.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace ricochet::diagnosis::detail {

std::string bias_text(const ErrorReport& r, int k) {
  std::vector<double> x;
  for (const auto& res : r.residual) x.push_back(res[k]);
  const MeanSe m = mean_se(x);
  if (!(m.se > 0)) return {};
  const double t = m.mean / m.se;
  if (std::fabs(t) < 3) return {};
  const double scale = k == kObsPenetration ? 1e3 : k == kObsDuration ? 1e3 : 1.0;
  const char* unit = k == kObsPenetration ? "mm" : k == kObsDuration ? "ms" : kObservableUnits[k];
  return fmt::format("measured {} is {} than predicted by {:.3g} {} on average (t = {:.1f})",
                     kObservableLabels[k], m.mean > 0 ? "larger" : "smaller",
                     std::fabs(m.mean) * scale, unit, t);
}

std::string evidence_of(const Candidate& c, const Baseline& b, const DiagnoseOptions& o) {
  const Assessment& base = b.base;
  std::vector<std::string> parts;
  if (c.effects.size() > 1)
    parts.push_back(fmt::format(
        "held-out error {:.4g} vs {:.4g} for the base model (against its first effect alone: "
        "corrected t = {:.2f}, p = {:.2g}, x {} pairs tried = {:.2g})",
        c.heldout_error, base.heldout.error.mean, c.t, c.p_value, c.family_size, c.p_adjusted));
  else
    parts.push_back(fmt::format(
        "{}; held-out error {:.4g} vs {:.4g} for the base model (drop {:.3g} +- {:.2g} "
        "over {} splits, corrected t = {:.2f}, p = {:.2g}, Holm-adjusted {:.2g}; penalty for {} "
        "added parameter{} {:.2g}; noise floor {:.4g})",
        std::isfinite(c.t)
            ? fmt::format("score test T = {:.2f} (p = {:.2g}; step-down max-T adjusted over {} "
                          "candidates {:.2g})",
                          c.t, c.p_value, c.family_size, c.p_adjusted)
            : std::string("no score test (too few releases, or the effect could not be probed)"),
        c.heldout_error, base.heldout.error.mean, c.error_drop, c.drop_se, base.cv.splits(),
        c.heldout_t, c.heldout_p, c.p_holm, c.added_parameters.size(),
        c.added_parameters.size() == 1 ? "" : "s", c.penalty, b.floor.value.mean));
  // The observable whose error falls most.
  int best_k = -1;
  double best_drop = 0;
  for (int k = 0; k < kObservables; ++k) {
    if (!base.use[k]) continue;
    const double d = base.heldout.term_mean[k] - c.assessment.heldout.term_mean[k];
    if (d > best_drop) best_drop = d, best_k = k;
  }
  if (best_k >= 0)
    parts.push_back(fmt::format("the {} error falls most ({:.3g} -> {:.3g})",
                                kObservableLabels[best_k], base.heldout.term_mean[best_k],
                                c.assessment.heldout.term_mean[best_k]));
  if (std::isfinite(c.signature_r))
    parts.push_back(fmt::format("its score test {} the base model's residuals (r = {:.2f})",
                                std::fabs(c.signature_r) > 0.3 ? "matches" : "weakly matches",
                                c.signature_r));
  if (!c.law.empty()) parts.push_back("calibrated law: " + c.law);
  if (c.effects.size() > 1)
    parts.push_back(c.beats_first ? "the pair beats its first effect alone"
                                  : "the pair does not beat its first effect alone");
  for (const auto& s : c.signature_trends) parts.push_back(s);
  if (c.contact_bias)
    for (int k : {kObsPenetration, kObsDuration})
      if (base.use[k])
        if (std::string s = bias_text(base.heldout, k); !s.empty()) parts.push_back(s);
  std::string text;
  for (const auto& p : parts) text += (text.empty() ? "" : "; ") + p;
  text += c.supported ? ": consistent with " + c.meaning
                      : fmt::format(
                            ": not supported (score-test adjusted p {:.2g} and held-out Holm p "
                            "{:.2g} both >= {:.2g}, or the held-out error does not fall)",
                            c.p_adjusted, c.p_holm, o.alpha / 2);
  return text;
}

std::string confidence_text(const LawConfidenceSet& cs, bool missing_physics) {
  if (cs.members.empty()) return {};
  const std::vector<Family> families = cs.families();
  std::string list;
  for (Family f : families) {
    std::string names;
    for (const LawMember& m : cs.members)
      if (m.families.front() == f) names += (names.empty() ? "" : ", ") + m.effect;
    list += fmt::format("{}{}: {}", list.empty() ? "" : "; ", family_name(f), names);
  }
  std::string text =
      cs.members.size() == 1
          ? fmt::format("Of {} laws judged, the data single out one at level {:.2g} ({})",
                        cs.models, cs.alpha, list)
          : fmt::format(
                "These data cannot tell apart {} of the {} laws judged, of {} famil{} (level "
                "{:.2g}): {}",
                cs.members.size(), cs.models, families.size(), families.size() == 1 ? "y" : "ies",
                cs.alpha, list);
  // `none` in the set says that no candidate beats the law as it stands; whether anything is
  // missing at all is the floor's question, which the verdict has answered.
  if (cs.holds_none())
    text += missing_physics ? "; the law as it stands is in the set: no candidate is needed "
                              "beside it, so what its error above the floor lacks is not among "
                              "the candidates"
                            : "; the law as it stands is in the set: perhaps nothing is missing";
  if (const auto& e = cs.encompassing) {
    std::string gone;
    std::vector<Family> listed;  // a family with two representatives is named once
    for (std::size_t a = 0; a < e->laws.size(); ++a)
      if (const int b = e->excluded_by[a];
          b >= 0 && std::find(listed.begin(), listed.end(), e->families[a]) == listed.end()) {
        listed.push_back(e->families[a]);
        gone += fmt::format("{}{} ({} explains what it leaves, t = {:.1f} > {:.2f})",
                            gone.empty() ? "" : ", ", family_name(e->families[a]),
                            e->laws[static_cast<std::size_t>(b)],
                            e->t[a][static_cast<std::size_t>(b)], e->critical);
      }
    if (!gone.empty()) text += "; calibrated on the set, these families' laws leave it: " + gone;
  }
  return text + ".";
}

std::string observables_text(const Obs& v, int digits) {
  std::string out;
  for (int k = 0; k < kObservables; ++k)
    if (std::isfinite(v[k]))
      out +=
          fmt::format("{}{:.{}g} {}", out.empty() ? "" : ", ", v[k], digits, kObservableUnits[k]);
  return out;
}

std::string detectable_text(const std::vector<Detectable>& rows, std::size_t releases) {
  if (rows.empty()) return {};
  std::string list;
  for (const Detectable& r : rows) {
    const std::string shift = observables_text(r.shift, 2);
    list += fmt::format("{}{}: {} ({}{})", list.empty() ? "" : "; ", family_name(r.family), r.law,
                        std::isfinite(r.value) ? "moves the predictions by " : "",
                        std::isfinite(r.value) ? shift : r.effect);
  }
  return fmt::format(
      "Weakest law of each family these {} releases would detect (power {:.0f} % at family-wise "
      "level {:.2g}): {}.",
      releases, 100 * rows.front().power, rows.front().level, list);
}

std::string summary_of(const Diagnosis& d, const DiagnoseOptions& o) {
  std::string text = verdict_text(d, o);
  if (const std::string s = confidence_text(d.confidence_set, d.verdict == "missing physics");
      !s.empty())
    text += " " + s;
  if (d.verdict != "missing physics")
    if (const std::string s =
            detectable_text(d.detectable, d.baseline.base.heldout.per_release.size());
        !s.empty())
      text += " " + s;
  return text;
}

std::string verdict_text(const Diagnosis& d, const DiagnoseOptions& o) {
  const Baseline& b = d.baseline;
  const Assessment& base = b.base;
  const Candidate* best =
      !d.ranking.empty() && d.ranking.front().supported ? &d.ranking.front() : nullptr;
  const std::string floor_text =
      fmt::format("held-out error {:.4g} is {:.2f} x the measurement noise floor {:.4g}",
                  base.heldout.error.mean, b.adequacy.ratio, b.floor.value.mean);
  // A single name only when the confidence set holds one family (issue 31): otherwise the best
  // supported candidate is one of several laws the data cannot tell apart.
  const std::size_t families = d.confidence_set.families().size();
  if (best)
    return fmt::format(
        "Missing physics: {}. {}: {} ({}), supported at family-wise level {:.2g} (score "
        "test max-T adjusted p {:.2g}, held-out test Holm p {:.2g}, over {} candidates): {}. "
        "Held-out error {:.4g} -> {:.4g}{}.",
        floor_text,
        families > 1 ? "Best ranked, one of several laws these data cannot tell apart" : "Found",
        best->effect, best->meaning, o.alpha, best->p_adjusted, best->p_holm, d.family_size,
        best->law.empty() ? best->effect : best->law, base.heldout.error.mean, best->heldout_error,
        best->adequacy.adequate ? ", within the noise floor" : ", still above the noise floor");
  if (d.verdict == "missing physics") {
    std::string s = fmt::format(
        "Missing physics beyond the candidates: {}, no candidate of {} is supported, but the "
        "residuals keep a deterministic structure (Holm-controlled): ",
        floor_text, d.family_size);
    for (std::size_t i = 0; i < d.unnamed_structure.size(); ++i)
      s += (i ? "; " : "") + d.unnamed_structure[i];
    return s + ".";
  }
  if (d.verdict == "scatter")
    return fmt::format(
        "Scatter beyond the measurement noise, no deterministic trend: {}; no candidate of {} "
        "is supported and no residual or parameter trend survives the multiplicity control. "
        "The excess is explained by the {}.",
        floor_text, d.family_size,
        b.scatter.computed ? b.scatter.description
        : base.population.calibrated.empty()
            ? std::string("release-to-release scatter of the data or a bias of the held law, "
                          "which a law with nothing calibrated (model file `calibrate = []`) "
                          "cannot tell apart: no parameter of it can spread between releases")
            : std::string("spread of the ground's parameters between releases"));
  if (d.verdict == "inconclusive") {
    std::string blind;
    for (const Detectable& r : d.detectable)
      if (std::find(d.underpowered.begin(), d.underpowered.end(), r.family) != d.underpowered.end())
        blind += fmt::format("{}{} ({})", blind.empty() ? "" : ", ", family_name(r.family),
                             std::isfinite(r.z_80) ? fmt::format("z {:.1f}", r.z_80)
                                                   : std::string("not within its bounds"));
    return fmt::format(
        "Inconclusive: held-out error {:.4g} is within the noise floor {:.4g} ({}; threshold "
        "{:.4g}) and no candidate of {} is supported, but these data could hide a law of {}: "
        "the weakest law of each of these families they would detect with 80 % power changes "
        "the predictions by more than z = {:.3g} (a noncentrality, the whitened change over "
        "the set), which `adequate` requires. Throws chosen by `ricochet design` would see "
        "more.",
        base.heldout.error.mean, b.floor.value.mean, b.floor.source, b.adequacy.threshold,
        d.family_size, blind, o.adequate_z);
  }
  return fmt::format(
      "The model is adequate: held-out error {:.4g} is within the noise floor {:.4g} ({}; "
      "threshold {:.4g}); no candidate of {} is supported, and a law of every family changing "
      "the predictions by z = {:.3g} would have been detected with 80 % power.",
      base.heldout.error.mean, b.floor.value.mean, b.floor.source, b.adequacy.threshold,
      d.family_size, o.adequate_z);
}

std::vector<std::string> unexplained_after(const Assessment& a, const NoiseFloor& floor,
                                           const Adequacy& q, const std::vector<Feature>& features,
                                           const TrendOptions& to, const std::string& who,
                                           const std::vector<Trend>* given) {
  std::vector<std::string> out;
  out.push_back(fmt::format(
      "{}: held-out error {:.4g} = {:.2f} x the noise floor {:.4g} ({})", who, a.heldout.error.mean,
      q.ratio, floor.value.mean,
      q.adequate ? "within the floor" : fmt::format("above the threshold {:.4g}", q.threshold)));
  // The orientation average's own error (unknown orientation: fit/orientation_rule.hpp).
  if (a.heldout.quadrature_error > 0)
    out.push_back(fmt::format(
        "{}: orientation quadrature error of the held-out error {:.2g} ({:.2g} % of it; the "
        "half rules' difference)",
        who, a.heldout.quadrature_error,
        100.0 * a.heldout.quadrature_error / std::max(a.heldout.error.mean, 1e-300)));
  // Per-observable excess over the floor.
  for (int k = 0; k < kObservables; ++k) {
    if (!a.use[k]) continue;
    const double ratio =
        floor.term_mean[k] > 0 ? a.heldout.term_mean[k] / floor.term_mean[k] : INFINITY;
    if (ratio > 2)
      out.push_back(fmt::format("{} error {:.3g} is {:.1f} x its noise floor {:.3g}",
                                kObservableLabels[k], a.heldout.term_mean[k], ratio,
                                floor.term_mean[k]));
  }
  // The base model's trends were decided in compare()'s family (residuals and parameters);
  // a candidate's residual trends form their own family.
  std::vector<Trend> trends = given ? *given : residual_trends(a.heldout, a.use, features, to);
  std::stable_sort(trends.begin(), trends.end(),
                   [](const Trend& x, const Trend& y) { return x.p < y.p; });
  // One line per residual: its strongest trend, then the other features it also trends with.
  // In a designed set the features move together (speeds campaign: |V_in|, V_in^x, V_in^y and
  // omega_in all scale at once) and one line per pair buried the conclusions in 28 near-copies.
  std::vector<std::string> quantities;
  for (const auto& t : trends)
    if (t.significant &&
        std::find(quantities.begin(), quantities.end(), t.quantity) == quantities.end())
      quantities.push_back(t.quantity);
  for (const auto& q : quantities) {
    std::string line, also;
    for (const auto& t : trends) {
      if (!t.significant || t.quantity != q) continue;
      if (line.empty())
        line = describe(t);
      else
        also += (also.empty() ? "" : ", ") + t.feature_label;
    }
    if (!also.empty()) line += "; also with " + also + " (features correlated in this set)";
    out.push_back(line);
  }
  for (int k : {kObsPenetration, kObsDuration})
    if (a.use[k])
      if (std::string s = bias_text(a.heldout, k); !s.empty()) out.push_back(s);
  if (out.size() == 1 && !q.adequate)
    out.push_back(
        "no residual trend with any impact feature: unstructured scatter (e.g. "
        "release-to-release variability of the ground, or a noise floor set too low)");
  return out;
}

}  // namespace ricochet::diagnosis::detail
