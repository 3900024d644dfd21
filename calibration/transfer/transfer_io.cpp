#include "transfer/transfer_io.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <span>
#include <stdexcept>

#include "common/csv.hpp"
#include "common/h5.hpp"
#include "report/plot.hpp"
#include "stats/stats.hpp"

namespace ricochet::transfer {
namespace {

using nlohmann::json;

constexpr std::array<const char*, 3> kUnits = {"m/s", "m/s", "rad/s"};
constexpr std::array<const char*, 3> kLabels = {"V^x", "V^y", "omega"};

json per_component(const Vel3& v) {
  json j = json::object();
  for (int c = 0; c < 3; ++c) j[kComponentNames[c]] = v[c];
  return j;
}

json matrix(const Mat3& m) {
  json j = json::array();
  for (const auto& row : m) j.push_back(json(row));
  return j;
}

json ks_json(const DistributionComparison& d, std::uint64_t seed, std::size_t reps) {
  json j = {{"seed", seed},
            {"replicates", reps},
            {"n_measured", d.n_measured},
            {"n_predicted", d.n_predicted}};
  for (int c = 0; c < 3; ++c)
    j[kComponentNames[c]] = {{"statistic", d.ks[c].statistic}, {"p_value", d.ks[c].p_value}};
  return j;
}

std::string where_clause(const std::string& where) {
  return where.empty() ? std::string() : ", where " + where;
}

}  // namespace

OptionProblems FitSampling::problems() const {
  OptionProblems p;
  check_range(p, "replicates", static_cast<double>(replicates), kReplicates);
  return p;
}

FitReport analyse_fit(const ImpactSet& set, const std::string& where, const FitSampling& sampling) {
  require_valid(sampling.problems(), "transfer::analyse_fit");
  FitReport r;
  r.where = where;
  r.n = set.size();
  r.seed = sampling.seed;
  r.replicates = sampling.replicates;
  r.diagonal = fit_diagonal(set);
  try {
    r.full = fit_full(set);
  } catch (const std::invalid_argument& e) {
    r.full_reason = e.what();
  }
  try {
    r.loo = leave_one_out(set);
  } catch (const std::invalid_argument& e) {
    r.loo_reason = e.what();
  }
  r.in = incident(set);
  r.out = reflected(set);
  r.predicted = sample_reflected(r.diagonal.model, r.in, r.replicates, r.seed);
  r.ks = compare_distributions(r.out, r.predicted);
  return r;
}

json to_json(const FitReport& r) {
  json j;
  j["where"] = r.where.empty() ? json(nullptr) : json(r.where);
  j["n"] = r.n;
  j["A"] = per_component(r.diagonal.model.a);
  j["dA"] = per_component(r.diagonal.model.delta_a);
  j["moments"] = {{"mean_in", per_component(r.diagonal.mean_in)},
                  {"mean_out", per_component(r.diagonal.mean_out)},
                  {"min_in", per_component(r.diagonal.min_in)},
                  {"max_in", per_component(r.diagonal.max_in)},
                  {"min_out", per_component(r.diagonal.min_out)},
                  {"max_out", per_component(r.diagonal.max_out)}};
  if (r.full) {
    const FullFit& f = *r.full;
    json off = json::array();
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        if (i != k)
          off.push_back({{"out", kComponentNames[i]},
                         {"in", kComponentNames[k]},
                         {"value", f.m[i][k]},
                         {"se", f.se[i][k]},
                         {"t", f.m[i][k] / f.se[i][k]}});
    j["full"] = {{"M", matrix(f.m)},
                 {"se", matrix(f.se)},
                 {"residual_std", per_component(f.residual_std)},
                 {"condition_number", f.condition_number},
                 {"off_diagonal", off}};
  } else {
    j["full"] = nullptr;
    j["full_unavailable"] = r.full_reason;
  }
  if (r.loo) {
    const LooComparison& l = *r.loo;
    json improves = json::object();
    for (int c = 0; c < 3; ++c) improves[kComponentNames[c]] = l.full_improves[c];
    j["loo"] = {{"rmse",
                 {{"constant", per_component(l.rmse_constant)},
                  {"diagonal", per_component(l.rmse_diagonal)},
                  {"diagonal_lsq", per_component(l.rmse_diagonal_lsq)},
                  {"full", per_component(l.rmse_full)}}},
                {"full_improves", improves}};
  } else {
    j["loo"] = nullptr;
    j["loo_unavailable"] = r.loo_reason;
  }
  j["ks"] = ks_json(r.ks, r.seed, r.replicates);
  return j;
}

void write_fit_csv(const std::string& path, const std::string& source, const FitReport& r) {
  CsvTable t;
  t.comment(fmt::format("ricochet transfer fit of {} ({} releases){}", source, r.n,
                        where_clause(r.where)));
  t.comment(fmt::format(
      "A, dA: paper Eq. 2; M_*: full 3x3 least-squares matrix row (V_out = M V_in), se_*: its "
      "standard errors; loo_*: leave-one-out RMSE; ks_*: measured vs predicted V_out (seed {}, "
      "{} rebounds per release)",
      r.seed, r.replicates));
  t.row({"component",
         "unit",
         "A",
         "dA",
         "mean_in",
         "mean_out",
         "min_in",
         "max_in",
         "min_out",
         "max_out",
         "M_vx",
         "M_vy",
         "M_w",
         "se_vx",
         "se_vy",
         "se_w",
         "loo_rmse_constant",
         "loo_rmse_diagonal",
         "loo_rmse_diagonal_lsq",
         "loo_rmse_full",
         "ks_D",
         "ks_p"});
  const auto num = CsvTable::num;
  const double nan = std::nan("");
  for (int c = 0; c < 3; ++c) {
    const auto& d = r.diagonal;
    std::vector<std::string> row = {kComponentNames[c],      kUnits[c],         num(d.model.a[c]),
                                    num(d.model.delta_a[c]), num(d.mean_in[c]), num(d.mean_out[c]),
                                    num(d.min_in[c]),        num(d.max_in[c]),  num(d.min_out[c]),
                                    num(d.max_out[c])};
    for (int k = 0; k < 3; ++k) row.push_back(num(r.full ? r.full->m[c][k] : nan));
    for (int k = 0; k < 3; ++k) row.push_back(num(r.full ? r.full->se[c][k] : nan));
    for (double v : {r.loo ? r.loo->rmse_constant[c] : nan, r.loo ? r.loo->rmse_diagonal[c] : nan,
                     r.loo ? r.loo->rmse_diagonal_lsq[c] : nan, r.loo ? r.loo->rmse_full[c] : nan,
                     r.ks.ks[c].statistic, r.ks.ks[c].p_value})
      row.push_back(num(v));
    t.row(row);
  }
  t.write(path);
}

void write_fit_h5(const std::string& path, const std::string& source, const FitReport& r) {
  {
    // Start from an empty file: --out FILE holds this run's results only.
    h5::File truncate(path, h5::File::Mode::kTruncate);
  }
  StoredModel m;
  m.diagonal = r.diagonal.model;
  if (r.full) {
    m.full = r.full->m;
    m.full_se = r.full->se;
    m.has_full = true;
  }
  m.source = source;
  m.where = r.where;
  m.n = r.n;
  write_model_h5(m, path);
  h5::File f(path, h5::File::Mode::kReadWrite);
  f.write("/transfer/mean_in", std::span<const double>(r.diagonal.mean_in));
  f.write("/transfer/mean_out", std::span<const double>(r.diagonal.mean_out));
  if (r.loo) {
    f.write("/transfer/loo/rmse_constant", std::span<const double>(r.loo->rmse_constant));
    f.write("/transfer/loo/rmse_diagonal", std::span<const double>(r.loo->rmse_diagonal));
    f.write("/transfer/loo/rmse_diagonal_lsq", std::span<const double>(r.loo->rmse_diagonal_lsq));
    f.write("/transfer/loo/rmse_full", std::span<const double>(r.loo->rmse_full));
  }
  std::vector<double> d, p;
  for (const auto& k : r.ks.ks) {
    d.push_back(k.statistic);
    p.push_back(k.p_value);
  }
  f.write("/transfer/ks/statistic", d);
  f.write("/transfer/ks/p_value", p);
  f.set_attr("/transfer/ks", "seed", static_cast<double>(r.seed));
  f.set_attr("/transfer/ks", "replicates", static_cast<double>(r.replicates));
  std::vector<double> pred;
  for (const Vel3& v : r.predicted) pred.insert(pred.end(), v.begin(), v.end());
  f.write("/transfer/predicted_vout", pred, {r.predicted.size(), 3});
  f.flush();
}

std::string format_fit(const std::string& source, const FitReport& r) {
  std::string s = fmt::format("Transfer matrix, paper Eq. 2: {} ({} releases{})\n", source, r.n,
                              where_clause(r.where));
  s += fmt::format("  {:<7}{:>9}   {:>7}{:>11}{:>11}\n", "", "A_ii", "dA_ii", "<V_in>", "<V_out>");
  for (int c = 0; c < 3; ++c)
    s += fmt::format("  {:<7}{:>9.3f} +-{:>7.3f}{:>11.3f}{:>11.3f}  [{}]\n", kLabels[c],
                     r.diagonal.model.a[c], r.diagonal.model.delta_a[c], r.diagonal.mean_in[c],
                     r.diagonal.mean_out[c], kUnits[c]);
  if (r.full) {
    s += fmt::format(
        "Full matrix by least squares, V_out = M V_in (standard errors; condition number "
        "{:.0f}):\n",
        r.full->condition_number);
    s += fmt::format("  {:<7}{:>22}{:>22}{:>22}\n", "", "x V^x_in", "x V^y_in", "x omega_in");
    for (int i = 0; i < 3; ++i) {
      s += fmt::format("  {:<7}", kLabels[i]);
      for (int k = 0; k < 3; ++k)
        s += fmt::format("{:>22}",
                         fmt::format("{:.4f} ({:.4f})", r.full->m[i][k], r.full->se[i][k]));
      s += "\n";
    }
  } else {
    s += "Full matrix: " + r.full_reason + "\n";
  }
  if (r.loo) {
    const auto& l = *r.loo;
    s += "Leave-one-out RMSE of the mean prediction:\n";
    s += fmt::format("  {:<16}{:>10}{:>10}{:>10}{:>10}  {}\n", "", "constant", "Eq. 2", "LSQ diag",
                     "full", "full better than Eq. 2");
    for (int c = 0; c < 3; ++c)
      s += fmt::format("  {:<16}{:>10.4f}{:>10.4f}{:>10.4f}{:>10.4f}  {}\n",
                       fmt::format("{} [{}]", kLabels[c], kUnits[c]), l.rmse_constant[c],
                       l.rmse_diagonal[c], l.rmse_diagonal_lsq[c], l.rmse_full[c],
                       l.full_improves[c] ? "yes" : "no");
  } else {
    s += "Leave-one-out: " + r.loo_reason + "\n";
  }
  s += fmt::format(
      "Measured vs Eq. 2 reflected velocities (two-sample KS; seed {}, {} rebounds per release):\n",
      r.seed, r.replicates);
  for (int c = 0; c < 3; ++c)
    s += fmt::format("  {:<7} D = {:.3f}  p = {:.3g}\n", kLabels[c], r.ks.ks[c].statistic,
                     r.ks.ks[c].p_value);
  return s;
}

void write_cdf_figure(const std::string& path, const std::string& title,
                      const std::vector<CdfRow>& rows) {
  report::Figure fig;
  fig.title = title;
  for (const CdfRow& row : rows)
    for (int c = 0; c < 3; ++c) {
      const std::string unit = kUnits[c];
      const std::string name = kLabels[c];
      report::Panel p = report::ecdf_panel(row.label + ": " + name, name + " [" + unit + "]",
                                           {{name + "_in (measured)", component(*row.in, c)},
                                            {name + "_out (measured)", component(*row.out, c)},
                                            {name + "_out (Eq. 2)", component(*row.predicted, c)}});
      p.series[0].color = report::colour::kGrey;
      p.series[1].color = report::colour::kBlack;
      p.series[2].color = report::colour::kBluishGreen;
      p.key = "";  // the default: under the plot, never over data
      fig.panels.push_back(std::move(p));
    }
  fig.width_px = 1350;
  fig.height_px = rows.size() <= 1 ? 420 : static_cast<int>(380 * rows.size() + 40);
  report::render(fig, path);
}

std::size_t PredictSampling::replicates_for(PredictIncidents incidents) const {
  return replicates.value_or(incidents == PredictIncidents::kGivenState ? kGivenStateReplicates
                                                                        : kMeasuredSetReplicates);
}

OptionProblems PredictSampling::problems() const {
  OptionProblems p;
  if (replicates) check_range(p, "replicates", static_cast<double>(*replicates), kReplicates);
  return p;
}

void sample_predictions(PredictReport& r, PredictIncidents incidents,
                        const PredictSampling& sampling) {
  require_valid(sampling.problems(), "transfer::sample_predictions");
  r.seed = sampling.seed;
  r.replicates = sampling.replicates_for(incidents);
  r.samples = sample_reflected(r.model, r.vin, r.replicates, r.seed);
  // A reflected vertical velocity that is not upwards is possible when A_yy + dA_yy > 0.
  r.nonphysical_vy = 0;
  for (const Vel3& s : r.samples) r.nonphysical_vy += s[kVy] <= 0;
}

json to_json(const PredictReport& r) {
  json doc;
  doc["seed"] = r.seed;
  doc["model"] = r.model_source;
  doc["model"]["A"] = per_component(r.model.a);
  doc["model"]["dA"] = per_component(r.model.delta_a);
  doc["incidents"] = r.vin.size();
  doc["replicates"] = r.replicates;
  doc["n_samples"] = r.samples.size();
  json sj = json::object();
  for (int c = 0; c < 3; ++c) {
    const stats::Summary s = stats::summarize(component(r.samples, c));
    sj[kComponentNames[c]] = {
        {"mean", s.mean}, {"std", s.std}, {"min", s.min}, {"max", s.max}, {"unit", kUnits[c]}};
  }
  doc["summary"] = sj;
  doc["nonphysical_vy"] = r.nonphysical_vy;
  if (r.ks) doc["ks"] = ks_json(*r.ks, r.seed, r.replicates);
  constexpr std::size_t kMaxJsonSamples = 10000;
  if (r.samples.size() <= kMaxJsonSamples) {
    json arr = json::array();
    for (const Vel3& s : r.samples) arr.push_back(json(s));
    doc["samples"] = arr;
  } else {
    doc["samples"] = nullptr;  // too many for a JSON document: use --out
  }
  return doc;
}

void write_predict_csv(const std::string& path, const PredictReport& r) {
  CsvTable t;
  const DiagonalModel& m = r.model;
  t.comment(fmt::format(
      "ricochet transfer predict, paper Eq. 2, seed {}, A = ({}, {}, {}), dA = ({}, {}, {})",
      r.seed, m.a[0], m.a[1], m.a[2], m.delta_a[0], m.delta_a[1], m.delta_a[2]));
  t.row({"incident", "replicate", "vin_x[m/s]", "vin_y[m/s]", "win[rad/s]", "vout_x[m/s]",
         "vout_y[m/s]", "wout[rad/s]"});
  for (std::size_t i = 0; i < r.vin.size(); ++i)
    for (std::size_t k = 0; k < r.replicates; ++k) {
      const Vel3& s = r.samples[i * r.replicates + k];
      t.row({r.ids[i], std::to_string(k), CsvTable::num(r.vin[i][0]), CsvTable::num(r.vin[i][1]),
             CsvTable::num(r.vin[i][2]), CsvTable::num(s[0]), CsvTable::num(s[1]),
             CsvTable::num(s[2])});
    }
  t.write(path);
}

void write_predict_h5(const std::string& path, const PredictReport& r) {
  h5::File f(path, h5::File::Mode::kTruncate);
  std::vector<double> in_flat, out_flat;
  std::vector<std::string> sample_ids;
  for (std::size_t i = 0; i < r.vin.size(); ++i)
    for (std::size_t k = 0; k < r.replicates; ++k) {
      const Vel3& s = r.samples[i * r.replicates + k];
      in_flat.insert(in_flat.end(), r.vin[i].begin(), r.vin[i].end());
      out_flat.insert(out_flat.end(), s.begin(), s.end());
      sample_ids.push_back(r.ids[i]);
    }
  f.write("/predict/vin", in_flat, {r.samples.size(), 3});
  f.write("/predict/vout", out_flat, {r.samples.size(), 3});
  f.write_strings("/predict/incident", sample_ids);
  f.set_attr("/predict", "seed", static_cast<double>(r.seed));
  f.set_attr("/predict", "replicates", static_cast<double>(r.replicates));
  f.set_attr("/predict", "units", std::string("m/s, m/s, rad/s"));
  f.write("/predict/A", std::span<const double>(r.model.a));
  f.write("/predict/dA", std::span<const double>(r.model.delta_a));
  f.flush();
}

std::string format_predict(const PredictReport& r) {
  const DiagonalModel& m = r.model;
  std::string s = fmt::format(
      "Eq. 2 prediction: {} samples ({} incident x {} rebounds), seed {}, A = ({:.3f}, {:.3f}, "
      "{:.3f}) +- ({:.3f}, {:.3f}, {:.3f})\n",
      r.samples.size(), r.vin.size(), r.replicates, r.seed, m.a[0], m.a[1], m.a[2], m.delta_a[0],
      m.delta_a[1], m.delta_a[2]);
  s += fmt::format("  {:<8}{:>10}{:>10}{:>10}{:>10}\n", "", "mean", "std", "min", "max");
  for (int c = 0; c < 3; ++c) {
    const stats::Summary x = stats::summarize(component(r.samples, c));
    s += fmt::format("  {:<8}{:>10.3f}{:>10.3f}{:>10.3f}{:>10.3f}  [{}]\n", kLabels[c], x.mean,
                     x.std, x.min, x.max, kUnits[c]);
  }
  if (r.nonphysical_vy)
    s += fmt::format("  warning: {} samples have V_out^y <= 0 (A_yy + dA_yy > 0)\n",
                     r.nonphysical_vy);
  if (r.ks)
    for (int c = 0; c < 3; ++c)
      s += fmt::format("  KS vs measured {:<6} D = {:.3f}  p = {:.3g}\n", kLabels[c],
                       r.ks->ks[c].statistic, r.ks->ks[c].p_value);
  return s;
}

}  // namespace ricochet::transfer
