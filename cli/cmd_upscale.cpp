// `ricochet upscale CAMPAIGN.h5`: the reduced engine's equivalent e_n^2, mu, mu_R fitted to the
// resolved impacts of a `ricochet dem campaign`, per impact and per set of grain-scale
// parameters, with identifiability, abacus figures and the gap to the lab. See
// docs/commands/upscale.md.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "fit/fit_io.hpp"
#include "impact/impact_set.hpp"
#include "model_options.hpp"
#include "params.hpp"
#include "shared_options.hpp"
#include "stats/lab_gap.hpp"
#include "upscale.hpp"

namespace ricochet::cli {
namespace {

struct UpscaleCliOptions {
  std::string campaign;
  ModelOptions model;
  std::vector<std::string> by;
  std::string where, lab, lab_where, figures, decks;
  /// --write-model: the campaign's equivalent law as a model file with nothing calibrated.
  std::string write_model;
  /// --lab-noise: the lab's measurement noise on V_out (m/s, m/s, rad/s), added to the resolved
  /// values before the KS test (stats::ks_with_measurement_noise); empty = not done.
  std::vector<double> lab_noise;
  std::size_t lab_noise_draws = stats::LabGapOptions{}.noise_draws;
  /// --lab-same-ids: keep only the lab releases whose ids the campaign's impacts (after --where)
  /// carry: a campaign run at lab states compared with those releases, not with the whole lab.
  bool lab_same_ids = false;
  /// --seed, --starts and --threads write into fit: their defaults are the fit module's.
  fit::FitOptions fit = dem::UpscaleOptions{}.fit;
  bool no_intervals = !fit::FitOptions{}.intervals;
  OutputOptions output;
};

nlohmann::json result_json(const dem::UpscaleResult& r) {
  nlohmann::json impacts = nlohmann::json::array();
  for (const auto& u : r.impacts) {
    nlohmann::json j = fit::to_json(u.fit);
    j["group"] = u.group;
    j["grain"] = u.grain;
    impacts.push_back(j);
  }
  nlohmann::json groups = nlohmann::json::array();
  for (const auto& g : r.groups) {
    std::vector<fit::ReleaseFit> member_fits;
    for (std::size_t i : g.members) member_fits.push_back(r.impacts[i].fit);
    groups.push_back({{"key", g.key},
                      {"grain", g.grain},
                      {"impacts", g.members.size()},
                      {"population", fit::to_json(g.population)},
                      {"per_impact_summary", fit::summary_json(member_fits)}});
  }
  nlohmann::json j = {
      {"source", r.source},
      {"shape", r.shape},
      {"by", r.by},
      {"impacts", impacts},
      {"groups", groups},
      {"seconds", r.seconds},
      {"noise",
       {{"source", r.noise_source},
        {"sigma_vout",
         {{"vx", r.noise_sigma[0]}, {"vy", r.noise_sigma[1]}, {"w", r.noise_sigma[2]}}}}}};
  if (r.campaign) j["campaign"] = fit::to_json(*r.campaign);
  return j;
}

void write_h5(const std::string& path, const dem::UpscaleResult& r, const Model& model,
              const Shape& shape, const fit::FitOptions& options) {
  {
    fit::ReleaseFitStore store(path, model, shape, r.set, options, false, "upscale/releases");
    std::vector<fit::ReleaseFit> fits;
    for (std::size_t i = 0; i < r.impacts.size(); ++i) {
      store.append(i, r.impacts[i].fit);
      fits.push_back(r.impacts[i].fit);
    }
    store.write_summary(fits, r.campaign ? &*r.campaign : nullptr, r.seconds);
  }
  h5::File f(path, h5::File::Mode::kReadWrite);
  f.set_attr("/upscale", "source", r.source);
  f.set_attr("/upscale", "by", nlohmann::json(r.by).dump());
  std::vector<std::string> keys, per_impact_group;
  for (const auto& g : r.groups) keys.push_back(g.key);
  for (const auto& u : r.impacts) per_impact_group.push_back(u.group);
  f.write_strings("/upscale/groups/key", keys);
  f.write_strings("/upscale/impact_group", per_impact_group);
  for (const auto& name : r.by) {
    std::vector<std::string> v;
    for (const auto& g : r.groups) v.push_back(g.grain.at(name));
    f.write_strings("/upscale/groups/grain/" + name, v);
  }
  if (r.groups.empty()) return;
  const auto& names = r.groups.front().population.names;
  for (std::size_t c : r.groups.front().population.calibrated) {
    std::vector<double> value, lo, hi;
    for (const auto& g : r.groups) {
      value.push_back(g.population.params[c]);
      double l = NAN, h = NAN;
      for (const auto& iv : g.population.intervals)
        if (iv.name == names[c]) l = iv.lo, h = iv.hi;
      lo.push_back(l);
      hi.push_back(h);
    }
    f.write("/upscale/groups/" + names[c], value);
    f.write("/upscale/groups/" + names[c] + "_lo", lo);
    f.write("/upscale/groups/" + names[c] + "_hi", hi);
  }
}

// The gap to the lab, in numbers: V_out (and the exit slip of a disc), the lab's own checks,
// then each parameter calibrated on both sides; into `j`, and as text.
struct LabGapText {
  std::string lab, params;
};
LabGapText add_lab_gap(const UpscaleCliOptions& o, const dem::UpscaleResult& r,
                       const ImpactSet& lab, const Shape& shape, nlohmann::json& j) {
  LabGapText text;
  stats::LabGapOptions g;
  if (!o.lab_noise.empty()) g.noise_sigma = Vel3{o.lab_noise[0], o.lab_noise[1], o.lab_noise[2]};
  g.noise_draws = o.lab_noise_draws;
  g.seed = o.fit.seed;
  if (shape.is_disc()) g.disc_radius_m = shape.rounding_radius_m;
  const stats::LabGap lab_gap = stats::lab_gap(r.set, lab, g);
  nlohmann::json gap;
  for (const auto& c : lab_gap.components) gap[c.name] = stats::to_json(c);
  j["gap_to_lab"] = gap;
  j["lab_checks"] = stats::checks_json(lab_gap);
  text.lab = stats::to_text(lab_gap);
  if (!o.lab_where.empty() || o.lab_same_ids)
    text.lab = fmt::format("  lab: the {} releases of {} {}\n", lab.size(), o.lab,
                           o.lab_same_ids ? "with the ids of the campaign's impacts"
                                          : "that match --lab-where") +
               text.lab;
  nlohmann::json params;
  if (!r.impacts.empty())
    for (std::size_t c : r.impacts.front().fit.calibrated) {
      std::vector<double> dem_v, lab_v;
      for (const auto& im : r.impacts) dem_v.push_back(im.fit.params[c]);
      for (const auto& f : r.lab_fits) lab_v.push_back(f.params[c]);
      const auto pg = stats::component_gap(r.impacts.front().fit.names[c], dem_v, lab_v);
      params[pg.name] = stats::to_json(pg);
      text.params += stats::to_text(pg);
    }
  j["parameters_vs_lab"] = params;
  return text;
}

void print_text(const dem::UpscaleResult& r, const std::optional<LabGapText>& lab_text,
                const std::vector<std::string>& figures) {
  std::cout << fmt::format(
      "upscale {}: {} {} impacts in {} group(s) by [{}], {:.1f} s\n", r.source, r.impacts.size(),
      r.shape, r.groups.size(),
      [&] {
        std::string s;
        for (const auto& b : r.by) s += (s.empty() ? "" : ", ") + b;
        return s;
      }(),
      r.seconds);
  std::cout << fmt::format(
      "  noise of V_out for the intervals: {} ({:.3g} m/s, {:.3g} m/s, {:.3g} rad/s)\n",
      r.noise_source == "replicates" ? "scatter of the replicate impacts"
                                     : "no replicates: the lab's operator scale (paper Table 1)",
      r.noise_sigma[0], r.noise_sigma[1], r.noise_sigma[2]);
  for (const auto& g : r.groups) {
    std::cout << fmt::format("  group {} ({} impacts): population fit", g.key, g.members.size());
    for (std::size_t c : g.population.calibrated)
      std::cout << fmt::format(" {} = {:.3f}", g.population.names[c], g.population.params[c]);
    std::cout << "\n";
    for (const auto& iv : g.population.intervals) std::cout << "    " << iv.statement << "\n";
  }
  for (const auto& u2 : r.impacts) {
    std::cout << fmt::format("  {}:", u2.id);
    for (std::size_t c : u2.fit.calibrated)
      std::cout << fmt::format(" {} = {:.3f}", u2.fit.names[c], u2.fit.params[c]);
    std::cout << fmt::format("  (Eq. 7 = {:.2g})\n", u2.fit.error);
  }
  if (lab_text) {
    std::cout << lab_text->lab;
    std::cout << "  equivalent parameters, resolved per impact against lab per release (one "
                 "engine):\n"
              << lab_text->params;
  }
  for (const auto& f : figures) std::cout << "  figure: " << f << "\n";
}

void run(const UpscaleCliOptions& o) {
  require_out_extension(o.output, {".h5", ".hdf5"});
  if (!o.write_model.empty()) require_extension("--write-model", o.write_model, {".toml"});
  const auto decks = dem::Decks::locate(o.decks);
  const Model model = o.model.build_model();
  const Shape shape = o.model.build_shape();
  dem::UpscaleOptions u;
  u.by = o.by;
  u.where = o.where;
  u.fit = o.fit;
  u.fit.engine.dt_s = o.model.engine_options().dt_s;
  if (u.fit.starts < 1) throw InputError("<command line>", 0, "--starts", "must be at least 1");
  u.fit.intervals = !o.no_intervals;
  if (!o.lab_noise.empty() && o.lab.empty())
    throw InputError("<command line>", 0, "--lab-noise", "needs --lab (the lab set it models)");
  if (!o.lab_where.empty() && o.lab.empty())
    throw InputError("<command line>", 0, "--lab-where", "needs --lab (the lab set it filters)");
  if (o.lab_same_ids && o.lab.empty())
    throw InputError("<command line>", 0, "--lab-same-ids", "needs --lab (the lab set it filters)");
  std::unique_ptr<ImpactSet> lab;
  if (!o.lab.empty())
    lab = std::make_unique<ImpactSet>(fit::select_shape(
        filter_nonempty(read_impact_set(o.lab), o.lab_where, o.lab, "--lab-where"), shape));
  u.lab = lab.get();
  u.lab_same_ids = o.lab_same_ids;
  const dem::UpscaleResult r = dem::upscale(o.campaign, decks, model, shape, u);

  std::vector<std::string> figures;
  if (!o.figures.empty()) figures = dem::write_upscale_figures(r, o.figures);
  std::optional<Model> law;
  if (!o.write_model.empty()) {
    // The campaign's one law (its population fit over every impact; one group's when it has
    // one), every parameter held: the reduced equivalent of the bed as a fixed base, e.g. for
    // `diagnose LAB --model FILE` (what the bed lacks, docs/resolved-model.md).
    const fit::PopulationFit& p = r.campaign ? *r.campaign : r.groups.front().population;
    law = model;
    law->set_values(p.params);
    // Held, not merely uncalibrated: a set with contact features would otherwise refit kn.
    for (std::size_t i = 0; i < law->parameter_count(); ++i) law->set_held(law->spec(i).name, true);
    write_text_file(
        o.write_model,
        fmt::format("# The equivalent law of {} (`ricochet upscale`, population fit "
                    "of {} impacts), held: nothing is calibrated, not even from contact "
                    "features.\n",
                    r.source, r.impacts.size()) +
            law->to_toml(),
        "--write-model");
  }
  if (!o.output.out.empty()) write_h5(o.output.out, r, model, shape, u.fit);

  nlohmann::json j = result_json(r);
  j["figures"] = figures;
  j["lab_where"] = o.lab_where;
  j["lab_same_ids"] = o.lab_same_ids;
  if (law) j["model_file"] = o.write_model;
  std::optional<LabGapText> lab_text;
  if (lab) lab_text = add_lab_gap(o, r, r.lab, shape, j);  // the lab as compared (same ids)
  if (o.output.json) {
    print_json(j);
    return;
  }
  print_text(r, lab_text, figures);
}

}  // namespace

void add_upscale_command(CLI::App& app) {
  auto o = std::make_shared<UpscaleCliOptions>();
  auto* sub = app.add_subcommand(
      "upscale", "Fit the reduced engine's e_n^2, mu, mu_R to resolved (LIGGGHTS) impacts");
  sub->add_option("campaign", o->campaign, "Campaign file of `ricochet dem campaign` (.h5)")
      ->required()
      ->check(CLI::ExistingFile);
  add_model_options(sub, o->model);
  sub->add_option("--by", o->by,
                  "Grain-scale parameters defining the groups, e.g. bed.E_grain_Pa (default: those "
                  "that vary)");
  // Not applied to --lab (--lab-where is): a campaign's filter may name its own columns (grain
  // parameters, resolved-only extras) that lab data do not have.
  add_where_option(sub, o->where, "the campaign's impacts");
  sub->add_option("--lab", o->lab,
                  "Lab impact set to compare V_out with (e.g. data/lab/cylinders.csv)");
  sub->add_option("--lab-noise", o->lab_noise,
                  "SX,SY,SW: the lab's measurement noise on V_out [m/s, m/s, rad/s], added to "
                  "the resolved values before the KS test against --lab (e.g. 0.1,0.1,8.3 for the "
                  "lab cylinders: docs/commands/upscale.md)")
      ->expected(3)
      ->delimiter(',');
  check_range(sub, "--lab-noise", 0, 1e3);
  sub->add_option("--lab-where", o->lab_where,
                  "Keep only the releases of --lab matching EXPR (docs/impact-sets.md, Filters), "
                  "e.g. the held-out half of a split; --where filters the campaign");
  sub->add_flag("--lab-same-ids", o->lab_same_ids,
                "Keep only the releases of --lab whose ids the campaign's impacts carry (after "
                "--where): a campaign run at lab states against those same releases");
  sub->add_option("--lab-noise-draws", o->lab_noise_draws, "Noise draws of --lab-noise")
      ->capture_default_str();
  check_range(sub, "--lab-noise-draws", 1, 1e6);
  add_figures_option(sub, o->figures);
  sub->add_option("--decks", o->decks, "liggghts-inputs folder (for the parameters' defaults)");
  add_seed_option(sub, o->fit.seed, "the calibration start design");
  sub->add_option("--starts", o->fit.starts, "BOBYQA runs per fit")->capture_default_str();
  add_threads_option(sub, o->fit.threads);
  check_range(sub, "--starts", 1, 1000);
  sub->add_option("--write-model", o->write_model,
                  "Write the campaign's equivalent law as a model file with nothing calibrated "
                  "(a fixed base for `diagnose --model`)");
  sub->add_flag("--no-intervals", o->no_intervals, "Skip the identifiability intervals");
  add_output_options(sub, o->output);
  sub->callback([o] { run(*o); });
}

}  // namespace ricochet::cli
