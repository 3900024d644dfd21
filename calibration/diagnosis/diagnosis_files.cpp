// The diagnosis module's files: compare, diagnose and ladder results as CSV tables or HDF5
// (the JSON they carry comes from diagnosis_json.cpp). Layouts in docs/commands/{compare,
// diagnose,ladder}.md.
#include <fmt/format.h>

#include <string>
#include <vector>

#include "common/csv.hpp"
#include "common/h5.hpp"
#include "diagnosis/diagnose.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::diagnosis {

// Per-release table: id, incident state, measured, held-out predicted, errors, floor.
void write_file(const std::string& path, const Baseline& b, const ImpactSet& set,
                const nlohmann::json& doc) {
  const auto& a = b.base;
  if (path.ends_with(".csv")) {
    CsvTable t;
    t.comment(
        "ricochet compare: per release, held-out predictions (each release predicted by a "
        "population fit that did not see it)");
    std::vector<std::string> header = {"id", "heldout_error", "insample_error", "noise_floor"};
    for (int k = 0; k < kObservables; ++k)
      if (a.use[k]) {
        const std::string unit = std::string("[") + kObservableUnits[k] + "]";
        header.push_back(std::string("predicted_") + kObservableNames[k] + unit);
        header.push_back(std::string("residual_") + kObservableNames[k] + unit);
      }
    t.row(header);
    for (std::size_t i = 0; i < set.size(); ++i) {
      std::vector<std::string> row = {set.impacts[i].id, CsvTable::num(a.heldout.per_release[i]),
                                      CsvTable::num(a.insample.per_release[i]),
                                      CsvTable::num(b.floor.per_release[i])};
      for (int k = 0; k < kObservables; ++k)
        if (a.use[k]) {
          row.push_back(CsvTable::num(a.heldout_predictions[i].value[k]));
          row.push_back(CsvTable::num(a.heldout.residual[i][k]));
        }
      t.row(row);
    }
    t.write(path);
    return;
  }
  {
    // Replace any old file, then store the compared set as /impacts (the file is itself an
    // impact set for the other tools).
    h5::File truncate(path, h5::File::Mode::kTruncate);
  }
  write_impact_set_h5(set, path, "impacts");
  h5::File f(path, h5::File::Mode::kReadWrite);
  std::vector<std::string> ids;
  for (const auto& im : set.impacts) ids.push_back(im.id);
  f.write_strings("/compare/releases/id", ids);
  f.write("/compare/releases/heldout_error", a.heldout.per_release);
  f.write("/compare/releases/insample_error", a.insample.per_release);
  f.write("/compare/releases/noise_floor", b.floor.per_release);
  for (int k = 0; k < kObservables; ++k) {
    if (!a.use[k]) continue;
    std::vector<double> pred, res;
    for (std::size_t i = 0; i < set.size(); ++i) {
      pred.push_back(a.heldout_predictions[i].value[k]);
      res.push_back(a.heldout.residual[i][k]);
    }
    const std::string n = kObservableNames[k];
    f.write("/compare/releases/predicted_" + n, pred);
    f.write("/compare/releases/residual_" + n, res);
    f.set_attr("/compare/releases/predicted_" + n, "unit", kObservableUnits[k]);
  }
  f.write("/compare/population/params", a.population.params);
  f.write_strings("/compare/population/names", a.population.names);
  f.set_attr("/compare", "json", doc.dump());
  f.set_attr("/compare", "noise_floor", b.floor.value.mean);
  f.set_attr("/compare", "heldout_error", a.heldout.error.mean);
  f.flush();
}

void write_file(const std::string& path, const Diagnosis& d, const nlohmann::json& doc) {
  if (path.ends_with(".csv")) {
    CsvTable t;
    t.comment("ricochet diagnose: " + d.summary);
    t.comment(fmt::format("noise floor {} ({}), base held-out error {}",
                          d.baseline.floor.value.mean, d.baseline.floor.source,
                          d.baseline.base.heldout.error.mean));
    t.row({"rank", "effect", "heldout_error", "error_drop", "drop_se", "penalty", "supported",
           "signature_r", "evidence"});
    for (std::size_t i = 0; i < d.ranking.size(); ++i) {
      const auto& c = d.ranking[i];
      t.row({std::to_string(i + 1), c.effect, CsvTable::num(c.heldout_error),
             CsvTable::num(c.error_drop), CsvTable::num(c.drop_se), CsvTable::num(c.penalty),
             c.supported ? "1" : "0", CsvTable::num(c.signature_r), c.evidence});
    }
    t.write(path);
    return;
  }
  h5::File f(path, h5::File::Mode::kTruncate);
  std::vector<std::string> names, evidence;
  std::vector<double> heldout, drop, se, supported;
  for (const auto& c : d.ranking) {
    names.push_back(c.effect);
    evidence.push_back(c.evidence);
    heldout.push_back(c.heldout_error);
    drop.push_back(c.error_drop);
    se.push_back(c.drop_se);
    supported.push_back(c.supported ? 1.0 : 0.0);
  }
  f.write_strings("/diagnosis/ranking/effect", names);
  f.write_strings("/diagnosis/ranking/evidence", evidence);
  f.write("/diagnosis/ranking/heldout_error", heldout);
  f.write("/diagnosis/ranking/error_drop", drop);
  f.write("/diagnosis/ranking/drop_se", se);
  f.write("/diagnosis/ranking/supported", supported);
  f.write("/diagnosis/releases/base_heldout_error", d.baseline.base.heldout.per_release);
  f.write("/diagnosis/releases/noise_floor", d.baseline.floor.per_release);
  f.set_attr("/diagnosis", "verdict", d.verdict);
  f.set_attr("/diagnosis", "noise_floor", d.baseline.floor.value.mean);
  f.set_attr("/diagnosis", "base_error", d.baseline.base.heldout.error.mean);
  f.set_attr("/diagnosis", "json", doc.dump());
  f.flush();
}

void write_file(const std::string& path, const Ladder& l, const nlohmann::json& doc) {
  if (path.ends_with(".csv")) {
    CsvTable t;
    t.comment(
        fmt::format("ricochet ladder; noise floor {} ({})", l.floor.value.mean, l.floor.source));
    std::vector<std::string> header = {"rung",          "added",      "model",   "insample_error",
                                       "heldout_error", "heldout_se", "adequate"};
    const auto& use = l.rungs.front().assessment.use;
    for (int k = 0; k < kObservables; ++k)
      if (use[k]) header.push_back(std::string("heldout_") + kObservableNames[k]);
    t.row(header);
    for (std::size_t r = 0; r < l.rungs.size(); ++r) {
      const auto& a = l.rungs[r].assessment;
      std::string model;
      for (const auto& e : l.rungs[r].effects) model += (model.empty() ? "" : "+") + e;
      std::vector<std::string> row = {std::to_string(r),
                                      l.rungs[r].added,
                                      model,
                                      CsvTable::num(a.insample.error.mean),
                                      CsvTable::num(a.heldout.error.mean),
                                      CsvTable::num(a.heldout.error.se),
                                      l.rungs[r].adequacy.adequate ? "1" : "0"};
      for (int k = 0; k < kObservables; ++k)
        if (use[k]) row.push_back(CsvTable::num(a.heldout.term_mean[k]));
      t.row(row);
    }
    t.write(path);
    return;
  }
  h5::File f(path, h5::File::Mode::kTruncate);
  std::vector<std::string> added;
  std::vector<double> ins, ho, se;
  for (const auto& r : l.rungs) {
    added.push_back(r.added.empty() ? "(base)" : r.added);
    ins.push_back(r.assessment.insample.error.mean);
    ho.push_back(r.assessment.heldout.error.mean);
    se.push_back(r.assessment.heldout.error.se);
  }
  f.write_strings("/ladder/added", added);
  f.write("/ladder/insample_error", ins);
  f.write("/ladder/heldout_error", ho);
  f.write("/ladder/heldout_se", se);
  f.set_attr("/ladder", "noise_floor", l.floor.value.mean);
  f.set_attr("/ladder", "json", doc.dump());
  f.flush();
}

}  // namespace ricochet::diagnosis
