// `ricochet transfer fit|predict`: the stochastic transfer-matrix rebound model (paper section 3,
// Eq. 2, Table 3, Figs. 11-12), the full 3x3 matrix and their comparison.
// See docs/commands/transfer.md for the options, the JSON keys and the equations.

#include <fmt/format.h>

#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "impact/impact_set.hpp"
#include "shared_options.hpp"
#include "transfer/transfer.hpp"
#include "transfer/transfer_io.hpp"

namespace ricochet::cli {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// fit

struct FitOptions {
  std::string data, where, split, figures;
  transfer::FitSampling sampling;  ///< --seed, --replicates: their defaults are the library's
  OutputOptions output;
};

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

// --split FEATURE=VALUE: the two subsets FEATURE < VALUE and FEATURE >= VALUE (paper Fig. 12,
// Table 3 rows 3-4 with vin_x=3.5), each with its own Eq. 2 fit.
struct Split {
  std::string feature;
  double value = 0;
  std::vector<transfer::FitReport> parts;  ///< below, above; empty without --split
};
Split split_fits(const FitOptions& o, const ImpactSet& set) {
  Split split;
  if (o.split.empty()) return split;
  const auto eq = o.split.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == o.split.size())
    throw InputError("<command line>", 0, "--split",
                     "expected FEATURE=VALUE, e.g. vin_x=3.5, got '" + o.split + "'");
  split.feature = o.split.substr(0, eq);
  try {
    std::size_t used = 0;
    split.value = std::stod(o.split.substr(eq + 1), &used);
    if (used != o.split.size() - eq - 1) throw std::invalid_argument("trailing characters");
  } catch (const std::exception&) {
    throw InputError("<command line>", 0, "--split",
                     "'" + o.split.substr(eq + 1) + "' is not a number");
  }
  const std::string value = o.split.substr(eq + 1);
  const std::string join = o.where.empty() ? "" : o.where + " && ";
  for (const std::string& cond : {split.feature + "<" + value, split.feature + ">=" + value}) {
    const ImpactSet sub = filter(set, cond);
    if (sub.empty())
      throw InputError("<command line>", 0, "--split",
                       "no release with " + cond + " in the selection");
    split.parts.push_back(transfer::analyse_fit(sub, join + cond, o.sampling));
  }
  return split;
}

std::vector<std::string> write_fit_figures(const FitOptions& o, const transfer::FitReport& main,
                                           const Split& split) {
  std::vector<std::string> figures;
  const std::string data_stem = fs::path(o.data).stem().string();
  const std::string stem = data_stem + (o.where.empty() ? "" : "_" + file_fragment(o.where));
  auto row = [&](const transfer::FitReport& r) {
    return transfer::CdfRow{data_stem + (r.where.empty() ? "" : " [" + r.where + "]") +
                                " (n=" + std::to_string(r.n) + ")",
                            &r.in, &r.out, &r.predicted};
  };
  const std::string path = (fs::path(o.figures) / ("transfer_cdf_" + stem + ".svg")).string();
  transfer::write_cdf_figure(
      path, "Transfer matrix (paper Eq. 2): incident, reflected and predicted CDFs", {row(main)});
  figures.push_back(path);
  if (!split.parts.empty()) {
    const std::string spath = (fs::path(o.figures) / ("transfer_cdf_" + stem + "_split_" +
                                                      file_fragment(split.feature) + ".svg"))
                                  .string();
    transfer::write_cdf_figure(spath, "Transfer matrix per subset (paper Fig. 12)",
                               {row(split.parts[0]), row(split.parts[1])});
    figures.push_back(spath);
  }
  return figures;
}

void run_fit(const FitOptions& o) {
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  refuse_problems(o.sampling.problems(), {{"replicates", "--replicates"}});
  const ImpactSet all = read_impact_set(o.data);
  const ImpactSet set = filter_nonempty(all, o.where, o.data);
  if (set.empty()) throw InputError(o.data, 0, "id", "the impact set has no release");
  const transfer::FitReport main = transfer::analyse_fit(set, o.where, o.sampling);
  const Split split = split_fits(o, set);
  const std::vector<std::string> figures =
      o.figures.empty() ? std::vector<std::string>{} : write_fit_figures(o, main, split);
  if (!o.output.out.empty()) {
    if (o.output.out.ends_with(".csv"))
      transfer::write_fit_csv(o.output.out, o.data, main);
    else
      transfer::write_fit_h5(o.output.out, o.data, main);
  }
  if (o.output.json) {
    json doc = transfer::to_json(main);
    doc["command"] = "transfer fit";
    doc["source"] = o.data;
    doc["units"] = {{"vx", "m/s"}, {"vy", "m/s"}, {"w", "rad/s"}};
    if (!split.parts.empty()) {
      doc["split"] = {{"feature", split.feature},
                      {"threshold", split.value},
                      {"below", transfer::to_json(split.parts[0])},
                      {"above", transfer::to_json(split.parts[1])}};
    }
    doc["figures"] = figures;
    doc["out"] = o.output.out.empty() ? json(nullptr) : json(o.output.out);
    print_json(doc);
    return;
  }
  std::cout << transfer::format_fit(o.data, main);
  for (const transfer::FitReport& p : split.parts)
    std::cout << "\n" << transfer::format_fit(o.data, p);
  for (const std::string& f : figures) std::cout << "wrote " << f << "\n";
  if (!o.output.out.empty()) std::cout << "wrote " << o.output.out << "\n";
}

// ---------------------------------------------------------------------------------------------
// predict

struct PredictOptions {
  std::string vin, incident, model, from, where, figures;
  transfer::PredictSampling sampling;  ///< --seed, --n: their defaults are the library's
  OutputOptions output;
};

// The transfer model to predict with: stored by `transfer fit --out FIT.h5` (--model), or
// fitted here on an impact set (--from).
void load_model(const PredictOptions& o, transfer::PredictReport& r) {
  if (!o.model.empty()) {
    const transfer::StoredModel m = transfer::read_model_h5(o.model);
    r.model = m.diagonal;
    r.model_source = {{"file", o.model},
                      {"source", m.source},
                      {"where", m.where.empty() ? json(nullptr) : json(m.where)},
                      {"n", m.n}};
    return;
  }
  const ImpactSet all = read_impact_set(o.from);
  const ImpactSet set = filter_nonempty(all, o.where, o.from);
  if (set.empty()) throw InputError(o.from, 0, "id", "the impact set has no release");
  r.model = transfer::fit_diagonal(set).model;
  r.model_source = {{"file", nullptr},
                    {"source", o.from},
                    {"where", o.where.empty() ? json(nullptr) : json(o.where)},
                    {"n", set.size()}};
}

// The incident states: --vin alone, or every release of --incident (returned, to compare with).
ImpactSet load_incident(const PredictOptions& o, const std::optional<Vel3>& given_vin,
                        transfer::PredictReport& r) {
  ImpactSet incident_set;
  if (given_vin) {
    r.vin.push_back(*given_vin);
    r.ids.push_back("vin");
    return incident_set;
  }
  incident_set = filter_nonempty(read_impact_set(o.incident), o.where, o.incident);
  if (incident_set.empty()) throw InputError(o.incident, 0, "id", "the impact set has no release");
  r.vin = transfer::incident(incident_set);
  for (const Impact& i : incident_set.impacts) r.ids.push_back(i.id);
  return incident_set;
}

void run_predict(const PredictOptions& o) {
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  if (o.vin.empty() == o.incident.empty())
    throw InputError("<command line>", 0, "--vin",
                     "give exactly one of --vin VX,VY,W and --incident DATA");
  // A transfer model maps any state: vy need not be negative.
  const std::optional<Vel3> given_vin =
      o.vin.empty() ? std::nullopt : std::optional(parse_vin(o.vin, /*falling=*/false));
  if (o.model.empty() == o.from.empty())
    throw InputError("<command line>", 0, "--model",
                     "give exactly one of --model FIT.h5 and --from DATA");
  refuse_problems(o.sampling.problems(), {{"replicates", "--n"}});

  transfer::PredictReport r;
  load_model(o, r);
  const ImpactSet incident_set = load_incident(o, given_vin, r);
  transfer::sample_predictions(r,
                               given_vin ? transfer::PredictIncidents::kGivenState
                                         : transfer::PredictIncidents::kMeasuredSet,
                               o.sampling);
  const std::vector<Vel3> measured = transfer::reflected(incident_set);
  if (!incident_set.empty()) r.ks = transfer::compare_distributions(measured, r.samples);

  std::vector<std::string> figures;
  if (!o.figures.empty()) {
    if (incident_set.empty())
      throw InputError("<command line>", 0, "--figures",
                       "figures compare with measurements: use --incident DATA");
    const std::string stem = fs::path(o.incident).stem().string();
    const std::string path = (fs::path(o.figures) / ("transfer_predict_" + stem + ".svg")).string();
    transfer::write_cdf_figure(path, "Transfer matrix (paper Eq. 2) prediction",
                               {{stem + " (n=" + std::to_string(incident_set.size()) + ")", &r.vin,
                                 &measured, &r.samples}});
    figures.push_back(path);
  }
  if (!o.output.out.empty()) {
    if (o.output.out.ends_with(".csv"))
      transfer::write_predict_csv(o.output.out, r);
    else
      transfer::write_predict_h5(o.output.out, r);
  }
  if (o.output.json) {
    json doc = transfer::to_json(r);
    doc["command"] = "transfer predict";
    doc["figures"] = figures;
    doc["out"] = o.output.out.empty() ? json(nullptr) : json(o.output.out);
    print_json(doc);
    return;
  }
  std::cout << transfer::format_predict(r);
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
  add_seed_option(fit, fo->sampling.seed,
                  "the predicted samples of the KS comparison and the figures");
  fit->add_option("--replicates", fo->sampling.replicates,
                  "Predicted rebounds per release for the KS comparison and the figures")
      ->capture_default_str();
  show_range(fit, "--replicates", transfer::FitSampling::kReplicates);
  add_figures_option(fit, fo->figures, "SVG CDF figures (paper Figs. 11-12)");
  add_output_options(fit, fo->output);
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
  predict->add_option("--n", po->sampling.replicates,
                      fmt::format("Rebounds per incident velocity (default {} with --vin, {} with "
                                  "--incident)",
                                  transfer::PredictSampling::kGivenStateReplicates,
                                  transfer::PredictSampling::kMeasuredSetReplicates));
  show_range(predict, "--n", transfer::PredictSampling::kReplicates);
  add_seed_option(predict, po->sampling.seed, "the random stream (required)")->required();
  add_figures_option(predict, po->figures, "an SVG CDF figure (with --incident)");
  add_output_options(predict, po->output);
  predict->callback([po] { run_predict(*po); });
}

}  // namespace ricochet::cli
