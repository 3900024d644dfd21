// `ricochet transfer fit|predict`: the stochastic transfer-matrix rebound model (paper section 3,
// Eq. 2, Table 3, Figs. 11-12), the full 3x3 matrix and their comparison.
// See docs/commands/transfer.md for the options, the JSON keys and the equations.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "impact/impact_set.hpp"
#include "report/plot.hpp"
#include "shared_options.hpp"
#include "stats/stats.hpp"
#include "transfer/transfer.hpp"

namespace ricochet::cli {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr std::array<const char*, 3> kUnits = {"m/s", "m/s", "rad/s"};
constexpr std::array<const char*, 3> kLabels = {"V^x", "V^y", "omega"};

json per_component(const Vel3& v) {
  json j = json::object();
  for (int c = 0; c < 3; ++c) j[kComponentNames[c]] = v[c];
  return j;
}

json matrix(const transfer::Mat3& m) {
  json j = json::array();
  for (const auto& row : m) j.push_back(json(row));
  return j;
}

// ---------------------------------------------------------------------------------------------
// fit

struct FitOptions {
  std::string data, where, split, figures;
  std::uint64_t seed = 1;
  std::size_t replicates = 100;
  OutputOptions output;
};

/// Everything `transfer fit` computes on one set.
struct FitResult {
  std::string where;
  std::size_t n = 0;
  transfer::DiagonalFit diagonal;
  std::optional<transfer::FullFit> full;
  std::optional<transfer::LooComparison> loo;
  std::vector<Vel3> in, out, predicted;
  transfer::DistributionComparison ks;
  std::string full_reason, loo_reason;  // why full / loo are absent
};

FitResult fit_set(const ImpactSet& set, const std::string& where, const FitOptions& o) {
  FitResult r;
  r.where = where;
  r.n = set.size();
  r.diagonal = transfer::fit_diagonal(set);
  try {
    r.full = transfer::fit_full(set);
  } catch (const std::invalid_argument& e) {
    r.full_reason = e.what();
  }
  try {
    r.loo = transfer::leave_one_out(set);
  } catch (const std::invalid_argument& e) {
    r.loo_reason = e.what();
  }
  r.in = transfer::incident(set);
  r.out = transfer::reflected(set);
  r.predicted = transfer::sample_reflected(r.diagonal.model, r.in, o.replicates, o.seed);
  r.ks = transfer::compare_distributions(r.out, r.predicted);
  return r;
}

json ks_json(const transfer::DistributionComparison& d, std::uint64_t seed, std::size_t reps) {
  json j = {{"seed", seed},
            {"replicates", reps},
            {"n_measured", d.n_measured},
            {"n_predicted", d.n_predicted}};
  for (int c = 0; c < 3; ++c)
    j[kComponentNames[c]] = {{"statistic", d.ks[c].statistic}, {"p_value", d.ks[c].p_value}};
  return j;
}

json fit_json(const FitResult& r, const FitOptions& o) {
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
    const transfer::FullFit& f = *r.full;
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
    const transfer::LooComparison& l = *r.loo;
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
  j["ks"] = ks_json(r.ks, o.seed, o.replicates);
  return j;
}

/// "vin_x<3.5" -> "vin_x_lt_3.5": a where-expression as a file-name fragment.
std::string file_fragment(const std::string& where) {
  std::string s;
  for (char ch : where) {
    if (std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '_' || ch == '-')
      s += ch;
    else if (ch == '<')
      s += "_lt_";
    else if (ch == '>')
      s += "_gt_";
    else if (ch == '=')
      s += "eq_";
    else if (ch == '!')
      s += "_not";
    else if (!s.empty() && s.back() != '_')
      s += '_';
  }
  return s;
}

/// One figure row: incident, measured reflected and predicted ECDFs for the three components
/// (paper Figs. 11-12: open symbols incident, solid reflected, green predicted).
std::vector<report::Panel> cdf_row(const std::string& label, const std::vector<Vel3>& in,
                                   const std::vector<Vel3>& out,
                                   const std::vector<Vel3>& predicted) {
  std::vector<report::Panel> panels;
  for (int c = 0; c < 3; ++c) {
    const std::string unit = kUnits[c];
    report::Panel p = report::ecdf_panel(
        label + ": " + kLabels[c], std::string(kLabels[c]) + " [" + unit + "]",
        {{std::string(kLabels[c]) + "_in (measured)", transfer::component(in, c)},
         {std::string(kLabels[c]) + "_out (measured)", transfer::component(out, c)},
         {std::string(kLabels[c]) + "_out (Eq. 2)", transfer::component(predicted, c)}});
    p.series[0].color = "#888888";
    p.series[1].color = "black";
    p.series[2].color = "#1a9641";
    p.key = "top left box opaque";
    panels.push_back(std::move(p));
  }
  return panels;
}

std::string row_label(const std::string& stem, const FitResult& r) {
  return stem + (r.where.empty() ? "" : " [" + r.where + "]") + " (n=" + std::to_string(r.n) + ")";
}

void write_fit_csv(const std::string& path, const std::string& source, const FitResult& r,
                   const FitOptions& o) {
  CsvTable t;
  t.comment(fmt::format("ricochet transfer fit of {} ({} releases){}", source, r.n,
                        r.where.empty() ? "" : ", where " + r.where));
  t.comment(fmt::format(
      "A, dA: paper Eq. 2; M_*: full 3x3 least-squares matrix row (V_out = M V_in), se_*: its "
      "standard errors; loo_*: leave-one-out RMSE; ks_*: measured vs predicted V_out (seed {}, "
      "{} rebounds per release)",
      o.seed, o.replicates));
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

void write_fit_h5(const std::string& path, const std::string& source, const FitResult& r,
                  const FitOptions& o) {
  {
    // Start from an empty file: --out FILE holds this run's results only.
    h5::File truncate(path, h5::File::Mode::kTruncate);
  }
  transfer::StoredModel m;
  m.diagonal = r.diagonal.model;
  if (r.full) {
    m.full = r.full->m;
    m.full_se = r.full->se;
    m.has_full = true;
  }
  m.source = source;
  m.where = r.where;
  m.n = r.n;
  transfer::write_model_h5(m, path);
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
  f.set_attr("/transfer/ks", "seed", static_cast<double>(o.seed));
  f.set_attr("/transfer/ks", "replicates", static_cast<double>(o.replicates));
  std::vector<double> pred;
  for (const Vel3& v : r.predicted) pred.insert(pred.end(), v.begin(), v.end());
  f.write("/transfer/predicted_vout", pred, {r.predicted.size(), 3});
  f.flush();
}

void print_fit(const std::string& source, const FitResult& r, const FitOptions& o) {
  std::cout << fmt::format("Transfer matrix, paper Eq. 2: {} ({} releases{})\n", source, r.n,
                           r.where.empty() ? "" : ", where " + r.where);
  std::cout << fmt::format("  {:<7}{:>9}   {:>7}{:>11}{:>11}\n", "", "A_ii", "dA_ii", "<V_in>",
                           "<V_out>");
  for (int c = 0; c < 3; ++c)
    std::cout << fmt::format("  {:<7}{:>9.3f} +-{:>7.3f}{:>11.3f}{:>11.3f}  [{}]\n", kLabels[c],
                             r.diagonal.model.a[c], r.diagonal.model.delta_a[c],
                             r.diagonal.mean_in[c], r.diagonal.mean_out[c], kUnits[c]);
  if (r.full) {
    std::cout << fmt::format(
        "Full matrix by least squares, V_out = M V_in (standard errors; condition number "
        "{:.0f}):\n",
        r.full->condition_number);
    std::cout << fmt::format("  {:<7}{:>22}{:>22}{:>22}\n", "", "x V^x_in", "x V^y_in",
                             "x omega_in");
    for (int i = 0; i < 3; ++i) {
      std::string line = fmt::format("  {:<7}", kLabels[i]);
      for (int k = 0; k < 3; ++k)
        line += fmt::format("{:>22}",
                            fmt::format("{:.4f} ({:.4f})", r.full->m[i][k], r.full->se[i][k]));
      std::cout << line << "\n";
    }
  } else {
    std::cout << "Full matrix: " << r.full_reason << "\n";
  }
  if (r.loo) {
    const auto& l = *r.loo;
    std::cout << "Leave-one-out RMSE of the mean prediction:\n";
    std::cout << fmt::format("  {:<16}{:>10}{:>10}{:>10}{:>10}  {}\n", "", "constant", "Eq. 2",
                             "LSQ diag", "full", "full better than Eq. 2");
    for (int c = 0; c < 3; ++c)
      std::cout << fmt::format("  {:<16}{:>10.4f}{:>10.4f}{:>10.4f}{:>10.4f}  {}\n",
                               fmt::format("{} [{}]", kLabels[c], kUnits[c]), l.rmse_constant[c],
                               l.rmse_diagonal[c], l.rmse_diagonal_lsq[c], l.rmse_full[c],
                               l.full_improves[c] ? "yes" : "no");
  } else {
    std::cout << "Leave-one-out: " << r.loo_reason << "\n";
  }
  std::cout << fmt::format(
      "Measured vs Eq. 2 reflected velocities (two-sample KS; seed {}, {} rebounds per release):\n",
      o.seed, o.replicates);
  for (int c = 0; c < 3; ++c)
    std::cout << fmt::format("  {:<7} D = {:.3f}  p = {:.3g}\n", kLabels[c], r.ks.ks[c].statistic,
                             r.ks.ks[c].p_value);
}

void run_fit(const FitOptions& o) {
  if (!o.output.out.empty()) require_extension("--out", o.output.out, {".csv", ".h5", ".hdf5"});
  if (o.replicates == 0)
    throw InputError("<command line>", 0, "--replicates", "must be at least 1");
  const ImpactSet all = read_impact_set(o.data);
  const ImpactSet set = filter_nonempty(all, o.where, o.data);
  if (set.empty()) throw InputError(o.data, 0, "id", "the impact set has no release");
  const FitResult main = fit_set(set, o.where, o);

  // --split FEATURE=VALUE: the two subsets FEATURE < VALUE and FEATURE >= VALUE (paper Fig. 12,
  // Table 3 rows 3-4 with vin_x=3.5), each with its own Eq. 2 fit.
  std::vector<FitResult> parts;
  std::string split_feature;
  double split_value = 0;
  if (!o.split.empty()) {
    const auto eq = o.split.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == o.split.size())
      throw InputError("<command line>", 0, "--split",
                       "expected FEATURE=VALUE, e.g. vin_x=3.5, got '" + o.split + "'");
    split_feature = o.split.substr(0, eq);
    try {
      std::size_t used = 0;
      split_value = std::stod(o.split.substr(eq + 1), &used);
      if (used != o.split.size() - eq - 1) throw std::invalid_argument("trailing characters");
    } catch (const std::exception&) {
      throw InputError("<command line>", 0, "--split",
                       "'" + o.split.substr(eq + 1) + "' is not a number");
    }
    const std::string value = o.split.substr(eq + 1);
    const std::string join = o.where.empty() ? "" : o.where + " && ";
    for (const std::string& cond : {split_feature + "<" + value, split_feature + ">=" + value}) {
      const ImpactSet sub = filter(set, cond);
      if (sub.empty())
        throw InputError("<command line>", 0, "--split",
                         "no release with " + cond + " in the selection");
      parts.push_back(fit_set(sub, join + cond, o));
    }
  }

  std::vector<std::string> figures;
  if (!o.figures.empty()) {
    const std::string stem =
        fs::path(o.data).stem().string() + (o.where.empty() ? "" : "_" + file_fragment(o.where));
    report::Figure fig;
    fig.title = "Transfer matrix (paper Eq. 2): incident, reflected and predicted CDFs";
    fig.panels = cdf_row(row_label(fs::path(o.data).stem().string(), main), main.in, main.out,
                         main.predicted);
    fig.width_px = 1350;
    fig.height_px = 420;
    const std::string path = (fs::path(o.figures) / ("transfer_cdf_" + stem + ".svg")).string();
    report::render_svg(fig, path);
    figures.push_back(path);
    if (!parts.empty()) {
      report::Figure split;
      split.title = "Transfer matrix per subset (paper Fig. 12)";
      for (const FitResult& p : parts)
        for (auto& panel :
             cdf_row(row_label(fs::path(o.data).stem().string(), p), p.in, p.out, p.predicted))
          split.panels.push_back(std::move(panel));
      split.width_px = 1350;
      split.height_px = 800;
      const std::string spath = (fs::path(o.figures) / ("transfer_cdf_" + stem + "_split_" +
                                                        file_fragment(split_feature) + ".svg"))
                                    .string();
      report::render_svg(split, spath);
      figures.push_back(spath);
    }
  }

  if (!o.output.out.empty()) {
    if (o.output.out.ends_with(".csv"))
      write_fit_csv(o.output.out, o.data, main, o);
    else
      write_fit_h5(o.output.out, o.data, main, o);
  }

  if (o.output.json) {
    json doc = fit_json(main, o);
    doc["command"] = "transfer fit";
    doc["source"] = o.data;
    doc["units"] = {{"vx", "m/s"}, {"vy", "m/s"}, {"w", "rad/s"}};
    if (!parts.empty()) {
      doc["split"] = {{"feature", split_feature},
                      {"threshold", split_value},
                      {"below", fit_json(parts[0], o)},
                      {"above", fit_json(parts[1], o)}};
    }
    doc["figures"] = figures;
    doc["out"] = o.output.out.empty() ? json(nullptr) : json(o.output.out);
    print_json(doc);
    return;
  }
  print_fit(o.data, main, o);
  for (const FitResult& p : parts) {
    std::cout << "\n";
    print_fit(o.data, p, o);
  }
  for (const std::string& f : figures) std::cout << "wrote " << f << "\n";
  if (!o.output.out.empty()) std::cout << "wrote " << o.output.out << "\n";
}

// ---------------------------------------------------------------------------------------------
// predict

struct PredictOptions {
  std::string vin, incident, model, from, where, figures;
  std::optional<std::size_t> n;
  std::uint64_t seed = 0;
  OutputOptions output;
};

void run_predict(const PredictOptions& o) {
  if (!o.output.out.empty()) require_extension("--out", o.output.out, {".csv", ".h5", ".hdf5"});
  if (o.vin.empty() == o.incident.empty())
    throw InputError("<command line>", 0, "--vin",
                     "give exactly one of --vin VX,VY,W and --incident DATA");
  // A transfer model maps any state: vy need not be negative.
  const std::optional<Vel3> given_vin =
      o.vin.empty() ? std::nullopt : std::optional(parse_vin(o.vin, /*falling=*/false));
  if (o.model.empty() == o.from.empty())
    throw InputError("<command line>", 0, "--model",
                     "give exactly one of --model FIT.h5 and --from DATA");
  if (o.n && *o.n == 0) throw InputError("<command line>", 0, "--n", "must be at least 1");

  transfer::DiagonalModel model;
  json model_doc;
  if (!o.model.empty()) {
    const transfer::StoredModel m = transfer::read_model_h5(o.model);
    model = m.diagonal;
    model_doc = {{"file", o.model},
                 {"source", m.source},
                 {"where", m.where.empty() ? json(nullptr) : json(m.where)},
                 {"n", m.n}};
  } else {
    const ImpactSet all = read_impact_set(o.from);
    const ImpactSet set = filter_nonempty(all, o.where, o.from);
    if (set.empty()) throw InputError(o.from, 0, "id", "the impact set has no release");
    model = transfer::fit_diagonal(set).model;
    model_doc = {{"file", nullptr},
                 {"source", o.from},
                 {"where", o.where.empty() ? json(nullptr) : json(o.where)},
                 {"n", set.size()}};
  }
  model_doc["A"] = per_component(model.a);
  model_doc["dA"] = per_component(model.delta_a);

  std::vector<Vel3> vin;
  std::vector<std::string> ids;
  ImpactSet incident_set;
  if (given_vin) {
    vin.push_back(*given_vin);
    ids.push_back("vin");
  } else {
    incident_set = filter_nonempty(read_impact_set(o.incident), o.where, o.incident);
    if (incident_set.empty())
      throw InputError(o.incident, 0, "id", "the impact set has no release");
    vin = transfer::incident(incident_set);
    for (const Impact& i : incident_set.impacts) ids.push_back(i.id);
  }
  const std::size_t reps = o.n.value_or(o.vin.empty() ? 1 : 1000);
  const std::vector<Vel3> samples = transfer::sample_reflected(model, vin, reps, o.seed);

  std::size_t nonphysical =
      0;  // reflected vertical velocity not upwards (possible when A_yy + dA_yy > 0)
  for (const Vel3& s : samples) nonphysical += s[kVy] <= 0;

  std::optional<transfer::DistributionComparison> ks;
  if (!incident_set.empty())
    ks = transfer::compare_distributions(transfer::reflected(incident_set), samples);

  std::vector<std::string> figures;
  if (!o.figures.empty()) {
    if (incident_set.empty())
      throw InputError("<command line>", 0, "--figures",
                       "figures compare with measurements: use --incident DATA");
    report::Figure fig;
    fig.title = "Transfer matrix (paper Eq. 2) prediction";
    const std::string stem = fs::path(o.incident).stem().string();
    fig.panels = cdf_row(stem + " (n=" + std::to_string(incident_set.size()) + ")", vin,
                         transfer::reflected(incident_set), samples);
    fig.width_px = 1350;
    fig.height_px = 420;
    const std::string path = (fs::path(o.figures) / ("transfer_predict_" + stem + ".svg")).string();
    report::render_svg(fig, path);
    figures.push_back(path);
  }

  if (!o.output.out.empty()) {
    if (o.output.out.ends_with(".csv")) {
      CsvTable t;
      t.comment(
          fmt::format("ricochet transfer predict, paper Eq. 2, seed {}, A = ({}, {}, {}), "
                      "dA = ({}, {}, {})",
                      o.seed, model.a[0], model.a[1], model.a[2], model.delta_a[0],
                      model.delta_a[1], model.delta_a[2]));
      t.row({"incident", "replicate", "vin_x[m/s]", "vin_y[m/s]", "win[rad/s]", "vout_x[m/s]",
             "vout_y[m/s]", "wout[rad/s]"});
      for (std::size_t i = 0; i < vin.size(); ++i)
        for (std::size_t r = 0; r < reps; ++r) {
          const Vel3& s = samples[i * reps + r];
          t.row({ids[i], std::to_string(r), CsvTable::num(vin[i][0]), CsvTable::num(vin[i][1]),
                 CsvTable::num(vin[i][2]), CsvTable::num(s[0]), CsvTable::num(s[1]),
                 CsvTable::num(s[2])});
        }
      t.write(o.output.out);
    } else {
      h5::File f(o.output.out, h5::File::Mode::kTruncate);
      std::vector<double> in_flat, out_flat;
      for (std::size_t i = 0; i < vin.size(); ++i)
        for (std::size_t r = 0; r < reps; ++r) {
          in_flat.insert(in_flat.end(), vin[i].begin(), vin[i].end());
          out_flat.insert(out_flat.end(), samples[i * reps + r].begin(),
                          samples[i * reps + r].end());
        }
      f.write("/predict/vin", in_flat, {samples.size(), 3});
      f.write("/predict/vout", out_flat, {samples.size(), 3});
      std::vector<std::string> sample_ids;
      for (std::size_t i = 0; i < vin.size(); ++i)
        for (std::size_t r = 0; r < reps; ++r) sample_ids.push_back(ids[i]);
      f.write_strings("/predict/incident", sample_ids);
      f.set_attr("/predict", "seed", static_cast<double>(o.seed));
      f.set_attr("/predict", "replicates", static_cast<double>(reps));
      f.set_attr("/predict", "units", std::string("m/s, m/s, rad/s"));
      f.write("/predict/A", std::span<const double>(model.a));
      f.write("/predict/dA", std::span<const double>(model.delta_a));
      f.flush();
    }
  }

  std::array<stats::Summary, 3> summary;
  for (int c = 0; c < 3; ++c) summary[c] = stats::summarize(transfer::component(samples, c));

  if (o.output.json) {
    json doc;
    doc["command"] = "transfer predict";
    doc["seed"] = o.seed;
    doc["model"] = model_doc;
    doc["incidents"] = vin.size();
    doc["replicates"] = reps;
    doc["n_samples"] = samples.size();
    json sj = json::object();
    for (int c = 0; c < 3; ++c)
      sj[kComponentNames[c]] = {{"mean", summary[c].mean},
                                {"std", summary[c].std},
                                {"min", summary[c].min},
                                {"max", summary[c].max},
                                {"unit", kUnits[c]}};
    doc["summary"] = sj;
    doc["nonphysical_vy"] = nonphysical;
    if (ks) doc["ks"] = ks_json(*ks, o.seed, reps);
    constexpr std::size_t kMaxJsonSamples = 10000;
    if (samples.size() <= kMaxJsonSamples) {
      json arr = json::array();
      for (const Vel3& s : samples) arr.push_back(json(s));
      doc["samples"] = arr;
    } else {
      doc["samples"] = nullptr;  // too many for a JSON document: use --out
    }
    doc["figures"] = figures;
    doc["out"] = o.output.out.empty() ? json(nullptr) : json(o.output.out);
    print_json(doc);
    return;
  }
  std::cout << fmt::format(
      "Eq. 2 prediction: {} samples ({} incident x {} rebounds), seed {}, A = ({:.3f}, {:.3f}, "
      "{:.3f}) +- ({:.3f}, {:.3f}, {:.3f})\n",
      samples.size(), vin.size(), reps, o.seed, model.a[0], model.a[1], model.a[2],
      model.delta_a[0], model.delta_a[1], model.delta_a[2]);
  std::cout << fmt::format("  {:<8}{:>10}{:>10}{:>10}{:>10}\n", "", "mean", "std", "min", "max");
  for (int c = 0; c < 3; ++c)
    std::cout << fmt::format("  {:<8}{:>10.3f}{:>10.3f}{:>10.3f}{:>10.3f}  [{}]\n", kLabels[c],
                             summary[c].mean, summary[c].std, summary[c].min, summary[c].max,
                             kUnits[c]);
  if (nonphysical)
    std::cout << fmt::format("  warning: {} samples have V_out^y <= 0 (A_yy + dA_yy > 0)\n",
                             nonphysical);
  if (ks)
    for (int c = 0; c < 3; ++c)
      std::cout << fmt::format("  KS vs measured {:<6} D = {:.3f}  p = {:.3g}\n", kLabels[c],
                               ks->ks[c].statistic, ks->ks[c].p_value);
  for (const std::string& f : figures) std::cout << "wrote " << f << "\n";
  if (!o.output.out.empty()) std::cout << "wrote " << o.output.out << "\n";
}

}  // namespace

void add_transfer_command(CLI::App& app) {
  CLI::App* transfer = app.add_subcommand(
      "transfer", "Stochastic transfer-matrix rebound model (paper Eq. 2, Table 3, Figs. 11-12)");
  transfer->require_subcommand(1);

  auto fo = std::make_shared<FitOptions>();
  CLI::App* fit = transfer->add_subcommand(
      "fit",
      "Identify A and dA (paper Eq. 2, Table 3), the full 3x3 matrix, their leave-one-out "
      "comparison and the KS comparison of measured and predicted reflected velocities");
  fit->add_option("DATA", fo->data, "Impact set (.csv, .h5 or .hdf5)")->required();
  add_where_option(fit, fo->where, "the releases of DATA");
  fit->add_option("--split", fo->split,
                  "Also fit the subsets FEATURE<VALUE and FEATURE>=VALUE, e.g. vin_x=3.5 (paper "
                  "Fig. 12)");
  add_seed_option(fit, fo->seed, "the predicted samples used by the KS comparison");
  fit->add_option("--replicates", fo->replicates,
                  "Predicted rebounds per release for the KS comparison and the figures")
      ->capture_default_str();
  add_figures_option(fit, fo->figures, "SVG CDF figures (paper Figs. 11-12)");
  add_output_options(fit, fo->output);
  check_range(fit, "--replicates", 1, 1e7);
  fit->callback([fo] { run_fit(*fo); });

  auto po = std::make_shared<PredictOptions>();
  CLI::App* predict = transfer->add_subcommand(
      "predict", "Sample reflected velocities with Eq. 2 (uniform A per rebound), seeded");
  add_vin_option(predict, po->vin, "One incident state");
  predict->add_option("--incident", po->incident,
                      "Impact set whose incident velocities are used (its V_out is compared)");
  predict->add_option("--model", po->model, "Model written by `transfer fit --out FIT.h5`");
  predict->add_option("--from", po->from, "Fit Eq. 2 on this impact set instead of --model");
  add_where_option(predict, po->where, "the releases of --from and --incident");
  predict->add_option(
      "--n", po->n, "Rebounds per incident velocity (default 1000 with --vin, 1 with --incident)");
  add_seed_option(predict, po->seed, "the random stream (required)")->required();
  add_figures_option(predict, po->figures, "an SVG CDF figure (with --incident)");
  add_output_options(predict, po->output);
  predict->callback([po] { run_predict(*po); });
}

}  // namespace ricochet::cli
