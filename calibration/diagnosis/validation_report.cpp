#include "diagnosis/validation_report.hpp"

#include <fmt/format.h>
#include <cmath>
#include <filesystem>
#include <map>

#include "common/paths.hpp"
#include "diagnosis/evidence.hpp"
#include "diagnosis/figures.hpp"
#include "diagnosis/force_history.hpp"
#include "diagnosis/inputs.hpp"
#include "diagnosis/track_figure.hpp"
#include "impact/impact_snapshot.hpp"
#include "report/html.hpp"
#include "report/impact_picture.hpp"
#include "stats/stats.hpp"

namespace ricochet::diagnosis {
namespace {

std::string g4(double v) {
  return std::isfinite(v) ? fmt::format("{:.4g}", v) : "-";
}
std::string g3(double v) {
  return std::isfinite(v) ? fmt::format("{:.3g}", v) : "-";
}
std::string f2(double v) {
  return std::isfinite(v) ? fmt::format("{:.2f}", v) : "-";
}
// A ratio to the noise floor: two decimals near 1, whole numbers from 100 on ("2092 x", not
// "2091.69 x": the decimals of so large a ratio mean nothing).
std::string ratio(double v) {
  return std::isfinite(v) && v >= 100 ? fmt::format("{:.0f}", v) : f2(v);
}

std::string effects_text(const std::vector<std::string>& e) {
  std::string s;
  for (const auto& x : e) s += (s.empty() ? "" : " + ") + x;
  return s;
}

std::string conclusion_of(const ReportSection& s) {
  const Diagnosis& d = s.diagnosis;
  const Baseline& b = d.baseline;
  std::string c = fmt::format(
      "{}: the model ({}) has a held-out error of {} against a noise floor of {} ({}), i.e. "
      "{} x the floor: {}.",
      s.input.label, effects_text(b.base.effects), g4(b.base.heldout.error.mean),
      g4(b.floor.value.mean), b.floor.source, f2(b.adequacy.ratio),
      b.adequacy.adequate ? "adequate" : "not adequate");
  if (b.floor.nearest_neighbour > 2 * b.floor.value.mean &&
      b.floor.nearest_neighbour > 0.5 * b.base.heldout.error.mean)
    c += fmt::format(
        " Releases with the most similar incident states differ from each other by an error of "
        "{} (nearest-neighbour check), {} x the floor: much of the error is scatter between "
        "releases (unmeasured orientation, ground preparation, measurement) that no "
        "deterministic effect of the model can remove.",
        g4(b.floor.nearest_neighbour), f2(b.floor.nearest_neighbour / b.floor.value.mean));
  c += " Verdict: " + d.verdict + ". " + d.summary;
  if (s.ladder.rungs.size() > 1) {
    const auto& last = s.ladder.rungs.back();
    c += fmt::format(" After the ladder ({}), the held-out error is {} = {} x the floor ({}).",
                     effects_text(last.effects), g4(last.assessment.heldout.error.mean),
                     f2(last.adequacy.ratio), last.adequacy.adequate ? "adequate" : "not adequate");
  }
  if (!d.unexplained.empty()) {
    c += " Left unexplained: ";
    for (std::size_t i = 0; i < d.unexplained.size(); ++i) c += (i ? "; " : "") + d.unexplained[i];
    c += ".";
  }
  return c;
}

// What fails, what was found, how far the error fell: one sentence.
std::string headline_of(const ReportSection& s) {
  const Diagnosis& d = s.diagnosis;
  const Baseline& b = d.baseline;
  const Assessment& a = b.base;
  int worst = -1;
  double worst_ratio = 0;
  for (int k = 0; k < kObservables; ++k)
    if (a.use[k] && b.floor.term_mean[k] > 0) {
      const double r = a.heldout.term_mean[k] / b.floor.term_mean[k];
      if (worst < 0 || r > worst_ratio) worst = k, worst_ratio = r;
    }
  std::string fails =
      b.adequacy.adequate
          ? fmt::format("The model is adequate: its held-out error is {} x the noise floor",
                        ratio(b.adequacy.ratio))
          : fmt::format("The model misses the data by {} x the noise floor",
                        ratio(b.adequacy.ratio));
  // A floor far below the error (data with tiny declared uncertainties, such as a simulation's
  // reconstruction errors) makes the ratio huge and says little: give the numbers behind it and
  // the model-free yardstick, how much releases with similar incident states differ.
  if (b.adequacy.ratio >= 20)
    fails += fmt::format(
        " (held-out error {} against a floor of {} from {}; releases with similar "
        "incident states differ by {})",
        g3(a.heldout.error.mean), g3(b.floor.value.mean),
        b.floor.source == "replicates"            ? "replicate releases"
        : b.floor.source == "borrowed replicates" ? "another set's replicate releases"
        : b.floor.source == "declared"            ? "the set's declared uncertainties"
                                                  : "the lab's uncertainties (paper Table 1)",
        g3(b.floor.nearest_neighbour));
  // An unknown orientation is part of the floor (assess.hpp): say how much, so that a ratio
  // against it is not read as a ratio against the measurement alone.
  if (b.floor.orientation_share > 0)
    fails += fmt::format(" (the floor {} includes {} from the spread over the unknown orientation)",
                         g3(b.floor.value.mean), g3(b.floor.orientation_share));
  if (!b.adequacy.adequate && worst >= 0)
    fails += fmt::format(", worst on {} ({} x its own floor)", kObservableLabels[worst],
                         ratio(worst_ratio));
  std::string found;
  const Candidate* best = nullptr;
  for (const auto& c : d.ranking)
    if (c.supported) {
      best = &c;
      break;
    }
  if (best)
    found = "the diagnosis finds " + best->effect + " missing";
  else if (d.verdict == "scatter")
    found = "the diagnosis finds no missing effect: the rest is scatter between releases";
  else if (b.adequacy.adequate)
    found = "no effect is needed";
  else
    found = "no candidate effect passes the family-wise test";
  std::string fell = "no effect was added";
  if (s.ladder.rungs.size() > 1) {
    const auto& last = s.ladder.rungs.back();
    std::string added;
    for (std::size_t r = 1; r < s.ladder.rungs.size(); ++r)
      added += (added.empty() ? "" : " and ") + s.ladder.rungs[r].added;
    fell = fmt::format("adding {} takes the held-out error from {} to {} x the floor", added,
                       ratio(s.ladder.rungs.front().adequacy.ratio), ratio(last.adequacy.ratio));
  }
  return fmt::format("{}; {}; {}.", fails, found, fell);
}

// One sentence: the set against the lab, on every release and without the lab's gross errors.
std::string lab_sentence_of(const stats::LabGap& g, const std::string& lab_data, std::size_t n,
                            bool matched) {
  std::string all, core, ks_all, ks_core;
  std::size_t n_core = n;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& c = g.components[k];
    const double gap = (c.model.mean - c.measured.mean) / c.measured.std;
    all += fmt::format("{}{} {:+.2f}", k ? ", " : "", c.name, gap);
    ks_all += fmt::format("{}{}", k ? ", " : "", g3(c.ks.p_value));
    if (c.measured_core && c.ks_core) {
      n_core = c.measured_core->n;
      core += fmt::format("{}{:+.2f}", k ? ", " : "",
                          (c.model.mean - c.measured_core->mean) / c.measured_core->std);
      ks_core += fmt::format("{}{}", k ? ", " : "", g3(c.ks_core->p_value));
    }
  }
  std::string out = fmt::format(
      "Against the lab ({}, {} releases{}): mean gaps in lab sd {}; two-sample KS p {}",
      shown_path(lab_data), n, matched ? ": those this set was run at" : "", all, ks_all);
  if (!core.empty())
    out +=
        fmt::format(". Against its {} releases without gross errors: gaps in their sd {}; KS p {}",
                    n_core, core, ks_core);
  if (g.components.size() > 3) {
    const auto& slip = g.components[3];
    out += fmt::format(
        ". Exit slip {:+.2f} m/s (lab {:+.2f}{})", slip.model.mean, slip.measured.mean,
        slip.measured_core
            ? fmt::format(", without its gross errors {:+.2f}", slip.measured_core->mean)
            : std::string());
  }
  return out + ".";
}

void lab_section(report::HtmlPage& page, const ReportSection& s) {
  const stats::LabGap& g = *s.lab_gap;
  std::vector<std::vector<std::string>> rows;
  for (const auto& c : g.components) {
    rows.push_back(
        {c.name, g4(c.model.mean) + " +- " + g3(c.model.std),
         g4(c.measured.mean) + " +- " + g3(c.measured.std),
         f2((c.model.mean - c.measured.mean) / c.measured.std), g3(c.ks.p_value),
         g4(c.model_robust.median) + " / " + g4(c.measured_robust.median),
         c.measured_core ? g4(c.measured_core->mean) + " +- " + g3(c.measured_core->std) : "-",
         c.ks_core ? g3(c.ks_core->p_value) : "-"});
  }
  page.table({"quantity", "this set", "lab", "gap [lab sd]", "KS p", "medians (set / lab)",
              "lab without gross errors", "KS p"},
             rows, "The set against the lab (SI units)");
  std::vector<std::string> flagged;
  for (std::size_t i = 0, n = 0; i < g.measured_gross_errors.flagged.size(); ++i)
    if (g.measured_gross_errors.flagged[i])
      flagged.push_back(g.flagged_ids[n++] + ": " + g.measured_gross_errors.why[i]);
  if (!flagged.empty()) {
    page.paragraph(
        "The lab's gross errors (modified z-score above 3.5 on a velocity, Iglewicz and "
        "Hoaglin 1993; the rule reads the lab alone):");
    page.list(flagged);
  }
  std::vector<std::string> response;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& r = g.response[k];
    response.push_back(fmt::format(
        "{} on {}: slope {} in this set, {} +- {} in the lab (reliability {}; equal-slope test "
        "p {}, Holm over three {})",
        kComponentNames[k], kComponentNames[k], f2(r.slope_model), f2(r.slope_measured),
        f2(r.se_measured), f2(r.reliability), g3(r.p_value), g3(g.response_p_holm[k])));
  }
  page.paragraph(
      "Does the lab's V_out follow its measured V_in as this set's does? A reliability "
      "near 0 says the lab's V_in scatter is reading noise (docs/commands/upscale.md).");
  page.list(response);
}

void data_section(report::HtmlPage& page, const ReportSection& s) {
  const ImpactSet& set = s.input.set;
  page.paragraph(fmt::format("{}: {} releases of shape {} from {}.", s.input.label, set.size(),
                             s.input.shape.name, shown_path(s.input.data)));
  if (!set.comments.empty()) page.list(set.comments);
  std::vector<std::vector<std::string>> rows;
  const char* cols[] = {"vin_x", "vin_y", "win", "vout_x", "vout_y", "wout"};
  const char* units[] = {"m/s", "m/s", "rad/s", "m/s", "m/s", "rad/s"};
  for (int c = 0; c < 6; ++c) {
    const auto sm = stats::summarize(set.feature(cols[c]));
    rows.push_back({std::string(cols[c]) + " [" + units[c] + "]", g4(sm.mean), g3(sm.std),
                    g4(sm.min), g4(sm.max)});
  }
  for (const char* f : {"alpha_in", "penetration", "contact_duration"}) {
    const auto v = set.feature(f);
    const auto sm = stats::summarize(v);
    if (sm.n > 0)
      rows.push_back({std::string(f) + (std::string(f) == "alpha_in"      ? " [rad]"
                                        : std::string(f) == "penetration" ? " [m]"
                                                                          : " [s]"),
                      g4(sm.mean), g3(sm.std), g4(sm.min), g4(sm.max)});
  }
  page.table({"quantity", "mean", "std (n-1)", "min", "max"}, rows,
             "Measured quantities (paper Table 2 layout)");
}

void compare_section(report::HtmlPage& page, const ReportSection& s) {
  const Baseline& b = s.diagnosis.baseline;
  const Assessment& a = b.base;
  std::vector<std::vector<std::string>> params;
  for (std::size_t i : a.population.calibrated)
    params.push_back({a.population.names[i], g4(a.population.params[i])});
  page.table({"parameter", "population fit"}, params,
             "Population calibration (one parameter set for all releases, fit module)");
  page.labelled("Noise floor",
                fmt::format("{} from {} ({}). Nearest-neighbour check: {}.", g4(b.floor.value.mean),
                            b.floor.source, b.floor.description, g4(b.floor.nearest_neighbour)));
  // An orientation-averaged set's error carries the average's own error (issue 35).
  const std::string quadrature =
      a.heldout.quadrature_error > 0
          ? fmt::format(" (standard error; the orientation average's quadrature error {})",
                        g3(a.heldout.quadrature_error))
          : std::string();
  page.labelled("Verdict",
                fmt::format("held-out error {} +- {}{} ({}-fold) = {} x the floor, adequacy "
                            "threshold {}: {}",
                            g4(a.heldout.error.mean), g3(a.heldout.error.se), quadrature, a.folds,
                            f2(b.adequacy.ratio), g4(b.adequacy.threshold),
                            b.adequacy.adequate ? "adequate" : "not adequate"));
  std::vector<std::vector<std::string>> rows;
  for (int k = 0; k < kObservables; ++k)
    if (a.use[k])
      rows.push_back({kObservableLabels[k], g4(a.insample.term_mean[k]), g4(a.heldout.term_mean[k]),
                      g4(b.floor.term_mean[k]), g3(a.heldout.rmse[k]) + " " + kObservableUnits[k],
                      f2(b.ks[k].statistic), g3(b.ks[k].p_value)});
  rows.push_back({"total", g4(a.insample.error.mean), g4(a.heldout.error.mean),
                  g4(b.floor.value.mean), "", "", ""});
  page.table({"observable", "in-sample error", "held-out error", "noise floor", "held-out RMSE",
              "KS D", "KS p"},
             rows, "Error per observable (mean squared relative error terms of Eq. 7)");
  std::vector<std::vector<std::string>> reg;
  for (const auto& r : b.regimes)
    reg.push_back({r.name, std::to_string(r.releases.size()), g4(r.heldout.mean), g3(r.heldout.se),
                   g4(r.floor.mean)});
  page.table({"regime", "releases", "held-out error", "SE", "noise floor"}, reg,
             "Error per regime");
  std::vector<std::string> trends;
  for (const auto* ts : {&b.residual_trends, &b.parameter_trends})
    for (const auto& t : *ts)
      if (t.significant) trends.push_back(describe(t));
  page.labelled("Significant trends (Pearson and Spearman p < 0.01)",
                trends.empty() ? "none" : std::to_string(trends.size()));
  if (!trends.empty()) page.list(trends);
  for (const auto& f : compare_figures(b, s.input.set, s.input.label))
    page.figure(f.figure, f.caption);
}

void diagnosis_section(report::HtmlPage& page, const ReportSection& s) {
  const Diagnosis& d = s.diagnosis;
  page.labelled("Verdict", d.verdict);
  page.paragraph(d.summary);
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < d.ranking.size(); ++i) {
    const auto& c = d.ranking[i];
    rows.push_back({std::to_string(i + 1), c.effect, g4(c.heldout_error), g3(c.error_drop),
                    g3(c.drop_se), f2(c.t), g3(c.p_adjusted), g3(c.p_holm),
                    c.supported ? "yes" : "no"});
  }
  page.table({"rank", "effect", "held-out error", "drop", "SE", "score T", "score p (max-T)",
              "held-out p (Holm)", "supported"},
             rows, "Candidate effects, best first");
  std::vector<std::string> ev;
  for (const auto& c : d.ranking) ev.push_back(c.effect + ": " + c.evidence);
  page.list(ev);
  // The laws these data cannot tell apart (issue 31): how each differs from the best in the
  // observables, so that a reader sees which throws could separate them.
  std::vector<std::vector<std::string>> set_rows;
  for (const LawMember& m : d.confidence_set.members) {
    set_rows.push_back({m.effect, std::string(family_name(m.family)),
                        std::string(variable_name(m.variable)), f2(m.statistic), m.law,
                        detail::observables_text(m.differs_from_best, 3)});
  }
  if (!set_rows.empty())
    page.table({"law", "family", "depends on", "score T", "law with its numbers",
                "differs from the best by (RMS)"},
               set_rows,
               fmt::format("Laws these data cannot tell apart (multiple comparisons with the best "
                           "at level {:.2g}), best first",
                           d.confidence_set.alpha));
  std::vector<std::vector<std::string>> power_rows;
  for (const Detectable& r : d.detectable) {
    power_rows.push_back({std::string(family_name(r.family)), r.effect, r.law,
                          std::isfinite(r.value) ? detail::observables_text(r.shift, 3) : "-",
                          std::isfinite(r.z_80) ? fmt::format("{:.1f}", r.z_80) : "-"});
  }
  if (!power_rows.empty() && d.verdict != "missing physics")
    page.table({"family", "most detectable law", "weakest law detected (80 % power)",
                "its change of the predictions (RMS)", "as a noncentrality z"},
               power_rows, "What this set could have detected");
  page.labelled("What it cannot explain", "");
  page.list(d.unexplained);
  for (const auto& f : diagnose_figures(d, s.input.label)) page.figure(f.figure, f.caption);
}

// The ladder's force histories (issue 33, item 3: the held-out force-history error rung by rung)
// against their replicate floor, where the set keeps histories.
void force_history_table(report::HtmlPage& page, const ReportSection& s) {
  if (s.force_history.empty()) return;
  const auto& floor = s.force_floor;
  std::vector<std::vector<std::string>> rows;
  for (std::size_t r = 0; r < s.force_history.size(); ++r) {
    std::vector<std::string> row = {std::to_string(r), s.ladder.rungs[r].added.empty()
                                                           ? "(base)"
                                                           : "+" + s.ladder.rungs[r].added};
    for (std::size_t c = 0; c < kForceComponents; ++c) {
      const double v = s.force_history[r].heldout_rms[c];
      const double se = s.force_history[r].heldout_se[c];
      const std::string value = std::isfinite(se) ? g4(v) + " +- " + g4(se) : g4(v);
      row.push_back(!std::isfinite(v) ? "-"
                    : floor && std::isfinite(floor->rms[c])
                        ? fmt::format("{} ({:.1f} x)", value, v / floor->rms[c])
                        : value);
    }
    rows.push_back(std::move(row));
  }
  std::string caption = fmt::format(
      "The contact force each rung gives along every release's own measured path against the "
      "measured one ({} releases): held-out RMS of measured minus model +- its standard error "
      "over the releases, normal and tangential force [N], moment [N m]",
      s.force_history.front().releases);
  if (floor)
    caption += fmt::format(
        "; in brackets over the replicate floor, one history's RMS distance from its replicates' "
        "mean ({} N, {} N, {} N m; {} groups of {} histories{}{})",
        g4(floor->rms[0]), g4(floor->rms[1]), g4(floor->rms[2]), floor->groups, floor->histories,
        floor->source.empty() ? "" : ", borrowed from " + shown_path(floor->source),
        floor->where.empty() ? "" : " (" + floor->where + ")");
  page.table({"rung", "added", "normal", "tangential", "moment"}, rows, caption);
}

void ladder_section(report::HtmlPage& page, const ReportSection& s) {
  const Ladder& l = s.ladder;
  std::vector<std::vector<std::string>> rows;
  for (std::size_t r = 0; r < l.rungs.size(); ++r) {
    const auto& rung = l.rungs[r];
    rows.push_back({std::to_string(r), rung.added.empty() ? "(base)" : "+" + rung.added,
                    g4(rung.assessment.insample.error.mean), g4(rung.assessment.heldout.error.mean),
                    g3(rung.assessment.heldout.error.se), f2(rung.adequacy.ratio),
                    rung.adequacy.adequate ? "yes" : "no"});
  }
  page.table({"rung", "added", "in-sample", "held-out", "SE", "x floor", "adequate"}, rows,
             "Model ladder chosen by rounds of diagnosis; noise floor " + g4(l.floor.value.mean));
  if (!l.stop_reason.empty()) page.labelled("Stopped", l.stop_reason);
  force_history_table(page, s);
}

// The contact figure of one impact (diagnosis/track_figure.hpp) with the reduced law at this
// set's population fit. A track that cannot be drawn is said, not fatal: the rest of the page
// stands without it.
void track_section(report::HtmlPage& page, const ReportSection& s, const Model& model,
                   const ReportOptions& o, const std::string& preferred_id) {
  try {
    const auto f = contact_track_figure(s.input.data, s.input.set, s.input.shape, model,
                                        s.diagnosis.baseline.base.population.params,
                                        o.diagnose.assess.fit.engine, preferred_id, s.input.label);
    if (f)
      page.figure(f->figure, f->caption +
                                 " The reduced law's parameters: its population fit on this set "
                                 "(Comparison below).");
  } catch (const std::exception& e) {
    page.paragraph("The contact in time is not shown: " + std::string(e.what()));
  }
}

// A set with contact histories: the discovered force law in words and the residual force before
// and after it (force_history.hpp). Like the contact figure, a failure is said, not fatal.
void force_section(report::HtmlPage& page, const ReportSection& s, const Model& model,
                   const ReportOptions& o) {
  if (!s.force_law_error.empty())
    page.paragraph("The force law from the contact histories is not shown: " + s.force_law_error);
  if (!s.force_law) return;
  try {
    const auto f = force_residual_figure(s.histories, model, s.input.shape,
                                         s.diagnosis.baseline.base.population.params,
                                         release_params_of(s.diagnosis, s.input.set.size()),
                                         *s.force_law, o.diagnose.assess.fit.engine, s.input.label);
    std::string law;
    for (const ComponentLaw& c : s.force_law->laws)
      law += (law.empty() ? "" : " ") + std::string(component_name(c.component)) + ": " + c.text +
             " (held-out residual " + g4(c.rms_residual) + " -> " + g4(c.heldout_rms) + ").";
    page.labelled("Force law from the contact histories", law);
    if (f) page.figure(f->figure, f->caption);
    page.table(residual_map_header(), residual_map_rows(s.force_law->map),
               "Where the base law fails along the contact: the residual force (measured - law) "
               "by branch (the law's penetration growing or not) and by depth h over each "
               "release's deepest h, mean over releases +- its standard error. A negative normal "
               "residual is a bed that pushes out less than the law; a negative tangential one "
               "(t along +x) a bed that holds the block back more.");
  } catch (const std::exception& e) {
    page.paragraph("The force residual is not shown: " + std::string(e.what()));
  }
}

}  // namespace

std::vector<ReportSection> analyse(const std::vector<ReportInput>& inputs, const Model& model,
                                   const ReportOptions& o) {
  require_valid(o.problems(), "diagnosis::analyse");
  std::vector<ReportSection> out;
  for (const auto& in : inputs) {
    ReportSection s;
    s.input = in;
    DiagnoseOptions d = o.diagnose;
    if (in.borrowed_floor) d.assess.borrowed_floor = in.borrowed_floor;
    s.diagnosis = diagnose(model, in.shape, in.set, d);
    s.ladder = auto_ladder(model, in.shape, in.set, o.rounds, d, &s.diagnosis);
    // The histories, read once: the force law the base model leaves (force_law_of's, each
    // release at its own fit), the ladder's force-history errors and their floor, and the
    // residual figure. A history that cannot be read is said on the page, not fatal.
    try {
      s.histories = measured_histories(in.data, in.set, in.shape);
      s.force_law = force_law_from_histories(
          s.histories, in.shape, model, s.diagnosis.baseline.base.population.params,
          o.diagnose.assess.fit.engine, {}, release_params_of(s.diagnosis, in.set.size()));
    } catch (const std::exception& e) {
      s.force_law_error = e.what();
    }
    if (s.force_law_error.empty()) {
      s.force_history = ladder_force_history(model, s.ladder, in.shape, s.histories,
                                             o.diagnose.assess.fit.engine);
      if (!s.force_history.empty())
        s.force_floor = force_history_floor(in.set, in.shape, s.histories, in.borrowed_floor);
    }
    s.headline = headline_of(s);
    s.conclusion = conclusion_of(s);
    if (in.lab) {
      stats::LabGapOptions g;
      if (in.shape.is_disc()) g.disc_radius_m = in.shape.rounding_radius_m;
      s.lab_gap = stats::lab_gap(in.set, *in.lab, g);
      s.lab_sentence = lab_sentence_of(*s.lab_gap, in.lab_data, in.lab->size(), in.lab_matched);
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::size_t write_report(const std::vector<ReportSection>& sections, const Model& model,
                         const ReportOptions& o, const std::string& path) {
  report::HtmlPage page(o.title);
  page.paragraph(
      "Compare the model with measurements, see where it fails, learn which physical effect is "
      "missing, add it and watch the error fall. Generated by `ricochet report`; every number "
      "comes from the fit module's calibrations (paper Eq. 7, section 4.2) and every figure is "
      "embedded in this file.");
  page.heading(2, "Conclusions", "conclusions");
  std::vector<std::string> items;
  for (const auto& s : sections) items.push_back(s.input.label + ": " + s.headline);
  page.list(items);

  page.heading(2, "Model", "model");
  page.paragraph("Base model: " + effects_text(model.effect_names()) +
                 ". Candidate effects: every registered effect not in the model.");
  std::vector<std::vector<std::string>> prm;
  for (std::size_t i = 0; i < model.parameter_count(); ++i) {
    const auto& sp = model.spec(i);
    prm.push_back({std::string(sp.name), std::string(sp.unit), g4(model.values()[i]),
                   g4(model.lower(i)) + " .. " + g4(model.upper(i)),
                   model.calibrated(i) ? "yes" : "no", std::string(sp.description)});
  }
  page.table({"parameter", "unit", "value", "bounds", "calibrated", "meaning"}, prm,
             "Parameters of the base model (start values)");

  page.heading(2, "Method", "method");
  page.list({
      "Error of a release: paper Eq. 7, the sum over V_out^x, V_out^y, omega_out of "
      "((simulated - measured) / max(|measured|, floor))^2, plus the same kind of term for the "
      "penetration and the contact duration when the data have them; blocks of unknown "
      "orientation are scored by the expected error over orientations.",
      "Held-out error: leak-free repeated k-fold cross-validation of the population fit (each "
      "release predicted by fits that saw neither it nor anything computed from it: start "
      "values, bounds and error scales come from the training releases).",
      "Noise floor: the expected error of the true model (replicates, declared uncertainties or "
      "the paper's Table 1 operator scale, plus the V_in noise propagated through the model and "
      "the orientation spread). Adequate: held-out error not significantly above it (paired "
      "test, 2 SE).",
      "Diagnosis: each candidate (catalog, plugins, and generated coefficient laws after a "
      "score-test screen) is added at its neutral value, recalibrated split by split and ranked "
      "by its penalised held-out error; supported when its drop passes the corrected "
      "resampled t-test under Holm's family-wise control at 0.05 and exceeds the penalty for "
      "the added parameters. Verdicts: adequate (within the floor, and a law of every family "
      "would have been seen at z 5), inconclusive (within the floor, but not so), scatter "
      "(release-to-release spread of the parameters, no deterministic trend), missing physics.",
  });

  // The section that pictured each file's first impact: a file given twice (a campaign's two
  // halves) shows its picture once, the second section points to it (the page has a size limit).
  std::map<std::string, std::string> pictured;
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const auto& s = sections[i];
    const std::string id = fmt::format("set{}", i + 1);
    // The verdict, then the ladder falling toward the floor; the numbers behind both are one
    // click away.
    page.heading(2, s.input.label, id);
    page.verdict(s.headline);
    for (const auto& f : ladder_figures(s.ladder, s.input.label)) page.figure(f.figure, f.caption);
    // A resolved campaign shows what the numbers are about: its first impact, through the contact.
    const auto snap = read_snapshot(s.input.data);
    const auto shown = pictured.find(s.input.data);
    if (snap && shown != pictured.end())
      page.paragraph(
          "This campaign's first impact, through the contact, is pictured in the "
          "section \"" +
          shown->second + "\" (the same file).");
    else if (snap) {
      page.figure(report::impact_picture(*snap, s.input.label),
                  "One impact of this campaign (LIGGGHTS), side view through the block's "
                  "mid-plane at frames through the contact: grains coloured by speed, the block's "
                  "spheres in grey. The crater, the bulge and the grains the block pushes.");
      pictured[s.input.data] = s.input.label;
    }
    // ... and, when the campaign keeps its tracks, that impact's contact in time beside the
    // reduced law at the same incident state: what upscaling asks the law to reproduce.
    track_section(page, s, model, o, snap ? snap->impact_id : std::string());
    force_section(page, s, model, o);
    if (s.lab_gap) {
      page.paragraph(s.lab_sentence);
      const double radius =
          s.input.shape.is_disc() ? s.input.shape.rounding_radius_m : std::nan("");
      const NamedFigure f =
          lab_gap_figure(s.input.set, *s.input.lab, *s.lab_gap, radius, s.input.label);
      page.figure(f.figure, f.caption);
    }
    page.begin_details("Conclusion in numbers");
    page.paragraph(s.conclusion);
    page.end_details();
    if (s.lab_gap) {
      page.begin_details("Against the lab in numbers");
      lab_section(page, s);
      page.end_details();
    }
    page.begin_details("Data");
    data_section(page, s);
    page.end_details();
    page.begin_details("Comparison: population fit, noise floor, errors, trends");
    compare_section(page, s);
    page.end_details();
    page.begin_details("Diagnosis: every candidate effect");
    diagnosis_section(page, s);
    page.end_details();
    page.begin_details("Model ladder in numbers");
    ladder_section(page, s);
    page.end_details();
  }
  page.write(path);
  return page.figures();
}

nlohmann::json to_json(const std::vector<ReportSection>& sections) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : sections) {
    const auto& d = s.diagnosis;
    nlohmann::json j = {{"label", s.input.label},
                        {"data", s.input.data},
                        {"shape", s.input.shape.name},
                        {"releases", s.input.set.size()},
                        {"verdict", d.verdict},
                        {"noise_floor", d.baseline.floor.value.mean},
                        {"noise_floor_source", d.baseline.floor.source},
                        {"base_error", d.baseline.base.heldout.error.mean},
                        {"best", d.ranking.empty() ? nlohmann::json(nullptr)
                                                   : nlohmann::json(d.ranking.front().effect)},
                        {"best_supported", !d.ranking.empty() && d.ranking.front().supported},
                        {"ladder", to_json(s.ladder)["rungs"]},
                        {"headline", s.headline},
                        {"conclusion", s.conclusion},
                        {"seconds", d.seconds}};
    if (!s.force_history.empty()) {
      j["force_history"] = nlohmann::json::array();
      for (const auto& e : s.force_history) j["force_history"].push_back(to_json(e));
    }
    if (s.force_floor) j["force_history_floor"] = to_json(*s.force_floor);
    if (s.lab_gap) {
      nlohmann::json c;
      for (const auto& g : s.lab_gap->components) c[g.name] = stats::to_json(g);
      j["against_lab"] = {{"data", s.input.lab_data},
                          {"releases", s.input.lab->size()},
                          {"matched_releases", s.input.lab_matched},
                          {"sentence", s.lab_sentence},
                          {"components", c},
                          {"checks", stats::checks_json(*s.lab_gap)}};
    }
    out.push_back(j);
  }
  return out;
}

}  // namespace ricochet::diagnosis
