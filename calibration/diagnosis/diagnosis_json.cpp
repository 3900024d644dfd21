// The JSON documents of compare, diagnose and ladder (docs/commands/*.md).
#include <cmath>

#include "common/json_number.hpp"
#include "diagnosis/diagnose.hpp"

namespace ricochet::diagnosis {

nlohmann::json to_json(const Assessment& a, const NoiseFloor& floor) {
  nlohmann::json params = nlohmann::json::object();
  for (std::size_t i = 0; i < a.population.names.size(); ++i)
    params[a.population.names[i]] = a.population.params[i];
  const Adequacy q = adequacy(a, floor);
  return {{"model", a.effects},
          {"calibrated", a.calibrated},
          {"parameters", params},
          {"insample_error", a.insample.error.mean},
          {"insample_se", a.insample.error.se},
          {"heldout_error", a.heldout.error.mean},
          {"heldout_se", a.heldout.error.se},
          {"heldout_quadrature_error", a.heldout.quadrature_error},
          {"insample_quadrature_error", a.insample.quadrature_error},
          {"folds", a.folds},
          {"split_errors", a.split_error},
          {"repeats", a.cv.repeats},
          {"insample_per_component", to_json(a.insample.term_mean, a.use)},
          {"heldout_per_component", to_json(a.heldout.term_mean, a.use)},
          {"heldout_rmse", to_json(a.heldout.rmse, a.use)},
          {"adequate", q.adequate},
          {"ratio_to_floor", q.ratio},
          {"adequacy_threshold", q.threshold},
          {"excess_over_floor", q.excess},
          {"excess_se", q.excess_se},
          {"seconds", a.seconds},
          {"collisions", a.collisions}};
}

nlohmann::json to_json(const Baseline& b, const ImpactSet& set) {
  nlohmann::json j = to_json(b.base, b.floor);
  j["noise_floor"] = to_json(b.floor, b.base.use);
  j["error_denominator_floors"] = to_json(b.error_floors, b.base.use);
  nlohmann::json releases = nlohmann::json::array();
  for (std::size_t i = 0; i < set.size(); ++i) {
    nlohmann::json r = {
        {"id", set.impacts[i].id},
        {"heldout_error", b.base.heldout.per_release[i]},
        {"insample_error", b.base.insample.per_release[i]},
        {"noise_floor", b.floor.per_release[i]},
        {"heldout_predicted", to_json(b.base.heldout_predictions[i].value, b.base.use)},
        {"heldout_quadrature_error",
         to_json(b.base.heldout_predictions[i].quadrature_error(), b.base.use)},
        {"heldout_residual", to_json(b.base.heldout.residual[i], b.base.use)}};
    if (!b.release_fits.empty()) {
      nlohmann::json p = nlohmann::json::object();
      const auto& f = b.release_fits[i];
      for (std::size_t c : f.calibrated) {
        nlohmann::json e = {{"value", f.params[c]}};
        if (const auto* iv = f.interval(f.names[c])) {
          e["interval"] = {iv->lo, iv->hi};
          e["identifiability"] = fit::identifiability_name(iv->status);
        }
        p[f.names[c]] = e;
      }
      r["release_fit"] = {{"error", f.error}, {"params", p}};
      if (std::isfinite(f.alpha_rad)) r["release_fit"]["alpha_in_rad"] = f.alpha_rad;
    }
    releases.push_back(r);
  }
  j["releases"] = releases;
  nlohmann::json regimes = nlohmann::json::array();
  for (const auto& r : b.regimes)
    regimes.push_back({{"name", r.name},
                       {"n", r.releases.size()},
                       {"heldout_error", r.heldout.mean},
                       {"heldout_se", r.heldout.se},
                       {"noise_floor", r.floor.mean}});
  j["regimes"] = regimes;
  j["scatter"] = to_json(b.scatter);
  nlohmann::json ks = nlohmann::json::object();
  for (int k = 0; k < kObservables; ++k)
    if (b.base.use[k])
      ks[kObservableNames[k]] = {{"statistic", b.ks[k].statistic}, {"p_value", b.ks[k].p_value}};
  j["ks"] = ks;
  j["residual_trends"] = to_json(b.residual_trends, true);
  j["parameter_trends"] = to_json(b.parameter_trends, true);
  j["features"] = nlohmann::json::array();
  for (const auto& f : b.features)
    j["features"].push_back({{"name", f.name}, {"label", f.label}, {"simulated", f.simulated}});
  return j;
}

nlohmann::json to_json(const Candidate& c, const std::array<bool, kObservables>& use) {
  nlohmann::json params = nlohmann::json::object();
  for (std::size_t i = 0; i < c.added_parameters.size() && i < c.added_values.size(); ++i)
    params[c.added_parameters[i]] = c.added_values[i];
  nlohmann::json j = {{"effect", c.effect},
                      {"effects", c.effects},
                      {"generated", c.generated},
                      {"law", c.law},
                      {"t", finite_or_null(c.t)},
                      {"p_value", finite_or_null(c.p_value)},
                      {"p_adjusted", finite_or_null(c.p_adjusted)},
                      {"p_holm", finite_or_null(c.p_holm)},
                      {"heldout_t", finite_or_null(c.heldout_t)},
                      {"heldout_p", finite_or_null(c.heldout_p)},
                      {"signature_trends", c.signature_trends},
                      {"heldout_error", finite_or_null(c.heldout_error)},
                      {"error_drop", finite_or_null(c.error_drop)},
                      {"evidence", c.evidence},
                      {"drop_se", finite_or_null(c.drop_se)},
                      {"penalty", finite_or_null(c.penalty)},
                      {"penalised_heldout_error", finite_or_null(c.penalised_heldout)},
                      {"supported", c.supported},
                      {"adequate_after", c.adequacy.adequate},
                      {"signature_r", finite_or_null(c.signature_r)},
                      {"meaning", c.meaning},
                      {"parameters", params}};
  if (c.error.empty()) {
    j["split_errors"] = c.assessment.split_error;
    j["insample_error"] = c.assessment.insample.error.mean;
    j["heldout_per_component"] = to_json(c.assessment.heldout.term_mean, use);
  } else {
    j["error"] = c.error;
  }
  return j;
}

nlohmann::json to_json(const LawConfidenceSet& cs, const std::array<bool, kObservables>& use) {
  nlohmann::json members = nlohmann::json::array();
  for (const LawMember& m : cs.members) {
    nlohmann::json families = nlohmann::json::array();
    for (Family f : m.families) families.push_back(family_name(f));
    members.push_back({{"effect", m.effect},
                       {"law", m.law},
                       {"family", family_name(m.family)},
                       {"families", families},
                       {"variable", variable_name(m.variable)},
                       {"statistic",
                        {{"T", finite_or_null(m.statistic)},
                         {"gap_to_best", finite_or_null(m.gap_to_best)},
                         {"mcb_critical", finite_or_null(m.critical)}}},
                       {"differs_from_best", to_json(m.differs_from_best, use)}});
  }
  nlohmann::json families = nlohmann::json::array();
  for (Family f : cs.families()) families.push_back(family_name(f));
  nlohmann::json out = {
      {"alpha", cs.alpha},
      {"laws_judged", cs.models},
      {"method",
       "multiple comparisons with the best (Hsu 1984) on the score statistics at alpha / 2, the "
       "law as it stands a reference of statistic 0, joint null by the multiplier bootstrap; "
       "then the families' calibrated laws by pairwise J tests (Davidson & MacKinnon 1981) at "
       "alpha / 2"},
      {"families", families},
      {"holds_none", cs.holds_none()},
      {"members", members},
      {"encompassing", nullptr}};
  if (const auto& e = cs.encompassing) {
    nlohmann::json laws = nlohmann::json::array();
    for (std::size_t a = 0; a < e->laws.size(); ++a) {
      nlohmann::json t = nlohmann::json::object();
      for (std::size_t b = 0; b < e->laws.size(); ++b)
        if (b != a) t[e->laws[b]] = finite_or_null(e->t[a][b]);
      const int by = e->excluded_by[a];
      laws.push_back(
          {{"effect", e->laws[a]},
           {"family", family_name(e->families[a])},
           {"law", e->calibrated[a]},
           {"excluded", by >= 0},
           {"excluded_by", by >= 0 ? nlohmann::json(e->laws[static_cast<std::size_t>(by)])
                                   : nlohmann::json(nullptr)},
           {"t", t}});
    }
    out["encompassing"] = {{"alpha", e->alpha},
                           {"critical", finite_or_null(e->critical)},
                           {"seconds", e->seconds},
                           {"laws", laws}};
  }
  return out;
}

nlohmann::json to_json(const std::vector<Detectable>& rows,
                       const std::array<bool, kObservables>& use) {
  nlohmann::json out = nlohmann::json::array();
  for (const Detectable& r : rows) {
    nlohmann::json curve = nlohmann::json::array();  // [change, E[T]] pairs (power.hpp)
    for (const auto& [change, t] : r.t_curve)
      curve.push_back({finite_or_null(change), finite_or_null(t)});
    out.push_back({{"family", family_name(r.family)},
                   {"variable", variable_name(r.variable)},
                   {"effect", r.effect},
                   {"parameter", r.parameter},
                   {"unit", r.unit},
                   {"neutral", finite_or_null(r.neutral)},
                   {"value", finite_or_null(r.value)},
                   {"change_80", finite_or_null(r.change_80)},
                   {"t_per_unit", finite_or_null(r.t_per_unit)},
                   {"t_ceiling", finite_or_null(r.t_ceiling)},
                   {"t_curve", std::move(curve)},
                   {"law", r.law},
                   {"shift", to_json(r.shift, use)},
                   {"noise_units", finite_or_null(r.noise_units)},
                   {"z_80", finite_or_null(r.z_80)},
                   {"power", r.power},
                   {"level", finite_or_null(r.level)},
                   {"critical_value", finite_or_null(r.critical)}});
  }
  return out;
}

nlohmann::json to_json(const Diagnosis& d) {
  const Baseline& b = d.baseline;
  nlohmann::json phases = nlohmann::json::object();
  for (const auto& [phase, n] : d.collisions_by_phase) phases[phase] = n;
  nlohmann::json ranking = nlohmann::json::array();
  for (const auto& c : d.ranking) ranking.push_back(to_json(c, b.base.use));
  nlohmann::json screened = nlohmann::json::array();
  for (const auto& s : d.screened_out)
    screened.push_back({{"effect", s.effect},
                        {"signature_r", finite_or_null(s.signature_r)},
                        {"t", finite_or_null(s.t)},
                        {"p_value", finite_or_null(s.p_value)},
                        {"p_adjusted", finite_or_null(s.p_adjusted)}});
  const nlohmann::json cs = to_json(d.confidence_set, b.base.use);
  nlohmann::json underpowered = nlohmann::json::array();
  for (Family f : d.underpowered) underpowered.push_back(family_name(f));
  return {{"verdict", d.verdict},
          {"underpowered_families", underpowered},
          {"adequate_z", finite_or_null(d.adequate_z)},
          {"confidence_set", cs["members"]},
          {"confidence_set_detail", cs},
          {"minimum_detectable", to_json(d.detectable, b.base.use)},
          {"minimum_detectable_by_candidate", to_json(d.detectable_candidates, b.base.use)},
          {"family_size", d.family_size},
          {"multiplicity", "step-down max-T over the family (Gaussian multiplier bootstrap)"},
          {"screened_out", screened},
          {"unnamed_structure", d.unnamed_structure},
          {"scatter", to_json(b.scatter)},
          {"cv",
           {{"folds", b.base.cv.folds},
            {"repeats", b.base.cv.repeats},
            {"splits", b.base.cv.splits()},
            {"seed", b.base.cv.seed}}},
          {"noise_floor", b.floor.value.mean},
          {"base_error", b.base.heldout.error.mean},
          {"ranking", ranking},
          {"summary", d.summary},
          {"unexplained", d.unexplained},
          {"noise_floor_source", b.floor.source},
          {"noise_floor_detail", to_json(b.floor, b.base.use)},
          {"error_denominator_floors", to_json(b.error_floors, b.base.use)},
          {"base", to_json(b.base, b.floor)},
          {"residual_trends", to_json(b.residual_trends, true)},
          {"parameter_trends", to_json(b.parameter_trends, true)},
          {"observables", to_json(Obs{1, 1, 1, 1, 1}, b.base.use)},
          {"seconds", d.seconds},
          {"collisions", d.collisions},
          {"collisions_by_phase", phases}};
}

nlohmann::json to_json(const Ladder& l) {
  nlohmann::json rungs = nlohmann::json::array();
  for (const auto& r : l.rungs) {
    nlohmann::json j = to_json(r.assessment, l.floor);
    j["added"] = r.added.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.added);
    j["law"] = r.law.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.law);
    if (r.split_discoveries > 0)
      j["split_discovery"] = {{"splits", r.split_discoveries}, {"same_terms", r.split_same_terms}};
    rungs.push_back(j);
  }
  nlohmann::json j = {
      {"rungs", rungs},
      {"noise_floor", l.floor.value.mean},
      {"noise_floor_detail",
       to_json(l.floor, l.rungs.empty()
                            ? std::array<bool, kObservables>{true, true, true, false, false}
                            : l.rungs.front().assessment.use)}};
  if (!l.rounds.empty()) {
    nlohmann::json rounds = nlohmann::json::array();
    for (const auto& d : l.rounds) {
      nlohmann::json r = {{"verdict", d.verdict},
                          {"summary", d.summary},
                          {"confidence_set", to_json(d.confidence_set, d.baseline.base.use)},
                          {"minimum_detectable", to_json(d.detectable, d.baseline.base.use)}};
      if (!d.ranking.empty())
        r["best"] = {{"effect", d.ranking.front().effect},
                     {"law", d.ranking.front().law},
                     {"t", finite_or_null(d.ranking.front().t)},
                     {"p_adjusted", finite_or_null(d.ranking.front().p_adjusted)},
                     {"p_holm", finite_or_null(d.ranking.front().p_holm)},
                     {"supported", d.ranking.front().supported},
                     {"error_drop", d.ranking.front().error_drop},
                     {"drop_se", d.ranking.front().drop_se}};
      rounds.push_back(r);
    }
    j["rounds"] = rounds;
    j["stop_reason"] = l.stop_reason;
  }
  return j;
}

}  // namespace ricochet::diagnosis
