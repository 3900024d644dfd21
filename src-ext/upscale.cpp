#include "upscale.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "campaign.hpp"
#include "common/clock.hpp"
#include "common/error.hpp"
#include "impact/impact_snapshot.hpp"
#include "report/impact_picture.hpp"
#include "report/plot.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;

std::map<std::string, std::map<std::string, std::string>> campaign_grain_parameters(
    const std::string& campaign_h5, const std::vector<CampaignEntry>& index, const Decks& decks) {
  std::map<std::string, std::map<std::string, std::string>> out;
  for (const auto& e : index) {
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(e.params);
    } catch (const std::exception&) {
      throw InputError(campaign_h5, 0, "/dem/index/params", "entry '" + e.id + "' is not JSON");
    }
    auto& g = out[e.id];
    // Recorded at run time when available (the decks' defaults may have changed since), else the
    // current defaults with the impact's overrides.
    for (const char* section : {"bed", "block"}) {
      const auto& params = std::string(section) == "bed" ? decks.bed_params : decks.block_params;
      const nlohmann::json* eff = j.contains("effective") && j["effective"].contains(section)
                                      ? &j["effective"][section]
                                      : nullptr;
      for (const auto& p : params) {
        std::string v = p.default_value;
        if (eff && eff->contains(p.name))
          v = (*eff)[p.name].get<std::string>();
        else if (j.contains(section) && j[section].contains(p.name))
          v = j[section][p.name].get<std::string>();
        else if (std::string(section) == "bed" && p.name == "seed" && j.contains("seed"))
          v = std::to_string(liggghts_seed(j["seed"].get<std::int64_t>(), 0));
        g[std::string(section) + "." + p.name] = v;
      }
    }
  }
  return out;
}

UpscaleResult upscale(const std::string& campaign_h5, const Decks& decks, const Model& model,
                      const Shape& shape, const UpscaleOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  UpscaleResult r;
  r.source = campaign_h5;
  r.shape = shape.name;
  ImpactSet all = read_impact_set_h5(campaign_h5);
  all = filter_nonempty(all, options.where, campaign_h5);
  r.set = fit::select_shape(all, shape);
  const auto grain =
      campaign_grain_parameters(campaign_h5, read_campaign_index(campaign_h5), decks);
  for (const auto& im : r.set.impacts)
    if (!grain.count(im.id))
      throw InputError(campaign_h5, 0, "/dem/index/id",
                       "impact '" + im.id + "' of /impacts is not in the campaign index");

  // Grouping parameters: given, or every grain-scale parameter that varies (not the seed).
  r.by = options.by;
  const auto& first = grain.at(r.set.impacts.front().id);
  if (r.by.empty()) {
    for (const auto& [name, value] : first) {
      if (name == "bed.seed") continue;
      for (const auto& im : r.set.impacts)
        if (grain.at(im.id).at(name) != value) {
          r.by.push_back(name);
          break;
        }
    }
  } else {
    for (const auto& name : r.by)
      if (!first.count(name)) {
        std::string known;
        for (const auto& [n, v] : first) known += (known.empty() ? "" : ", ") + n;
        throw InputError("<command line>", 0, "--by",
                         "unknown grain-scale parameter '" + name + "'; known: " + known);
      }
  }

  // Noise of a resolved V_out for the intervals. The reconstruction errors of a clean simulated
  // track (about 1e-3 m/s) say how well V_out is measured, not how reproducible the impact is:
  // with them alone every parameter of every impact came out "identified" in a narrow interval
  // while mu scattered from 0.25 to 1.9 between neighbouring impacts. The scatter between
  // replicas (other bed, other position) is that reproducibility; without replicas the lab's
  // operator scale stands in for it, so that resolved and lab intervals mean the same thing.
  {
    const auto replicas = replicate_groups(r.set);
    const Vel3 sd = pooled_vout_sd(r.set, replicas);
    // Identical replicas (a deterministic stand-in for LIGGGHTS) carry no noise estimate.
    const bool pooled = replicas.size() >= 2 && sd[0] > 0 && sd[1] > 0 && sd[2] > 0;
    r.noise_source = pooled ? "replicates" : "table1";
    r.noise_sigma = pooled ? sd : options.fit.sigma;
    for (auto& im : r.set.impacts) {
      Vel3 s = r.noise_sigma;
      if (im.sigma_vout)
        for (int k = 0; k < 3; ++k) s[k] = std::hypot(s[k], (*im.sigma_vout)[k]);
      im.sigma_vout = s;
    }
  }

  // Per-impact calibration (paper Eq. 7, with intervals), then groups.
  const std::vector<fit::ReleaseFit> fits =
      fit::calibrate_releases(model, shape, r.set, options.fit);
  std::map<std::string, std::size_t> group_index;
  for (std::size_t i = 0; i < r.set.size(); ++i) {
    UpscaleImpact u;
    u.id = r.set.impacts[i].id;
    u.fit = fits[i];
    std::string key;
    for (const auto& name : r.by) {
      u.grain[name] = grain.at(u.id).at(name);
      key += (key.empty() ? "" : " ") + name + "=" + u.grain[name];
    }
    u.group = key.empty() ? "all" : key;
    auto [it, added] = group_index.emplace(u.group, r.groups.size());
    if (added) {
      UpscaleGroup g;
      g.key = u.group;
      g.grain = u.grain;
      r.groups.push_back(g);
    }
    r.groups[it->second].members.push_back(i);
    r.impacts.push_back(std::move(u));
  }
  for (auto& g : r.groups) {
    ImpactSet sub = r.set;
    sub.impacts.clear();
    for (std::size_t i : g.members) sub.impacts.push_back(r.set.impacts[i]);
    g.population = fit::calibrate_population(model, shape, sub, options.fit);
  }
  if (r.groups.size() > 1) r.campaign = fit::calibrate_population(model, shape, r.set, options.fit);
  if (options.lab && !options.lab->impacts.empty()) {
    r.lab = *options.lab;
    if (options.lab_same_ids) {
      std::set<std::string> ids;
      for (const auto& im : r.set.impacts) ids.insert(im.id);
      std::erase_if(r.lab.impacts, [&](const Impact& im) { return !ids.contains(im.id); });
      if (r.lab.empty())
        throw InputError(
            r.lab.source, 0, "--lab-same-ids",
            "no release of " + r.lab.source + " has the id of an impact of " + campaign_h5);
    }
    r.lab_fits = fit::calibrate_releases(model, shape, r.lab, options.fit);
  }
  r.seconds = seconds_since(start);
  return r;
}

namespace {

double number_or_nan(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  return end && *end == '\0' && end != s.c_str() ? v : std::nan("");
}

}  // namespace

namespace {

// Fitted parameters per impact against the incident state (|V_in|, then omega_in), one series
// per group, with each impact's near-optimal interval.
report::Figure parameters_figure(const UpscaleResult& r) {
  const auto& names = r.impacts.front().fit.names;
  const auto& calibrated = r.impacts.front().fit.calibrated;
  report::Figure fig;
  fig.title =
      "Equivalent contact parameters of resolved impacts (" + r.shape + ", " + r.source + ")";
  fig.columns = static_cast<int>(calibrated.size());
  fig.height_px = 800;
  for (const char* axis : {"speed_in", "win"}) {
    for (std::size_t c : calibrated) {
      report::Panel p;
      p.title = names[c];
      p.xlabel = std::string(axis) == "speed_in" ? "|V_in| [m/s]" : "omega_in [rad/s]";
      p.ylabel = names[c];
      for (const auto& g : r.groups) {
        report::Series s;
        s.title = g.key;
        s.style = "errorbars";
        for (std::size_t i : g.members) {
          const Impact& im = r.set.impacts[i];
          const auto& f = r.impacts[i].fit;
          s.x.push_back(std::string(axis) == "speed_in" ? std::hypot(im.vin[kVx], im.vin[kVy])
                                                        : im.vin[kW]);
          s.y.push_back(f.params[c]);
          const auto* iv = f.interval(names[c]);
          s.ylo.push_back(iv ? iv->lo : f.params[c]);
          s.yhi.push_back(iv ? iv->hi : f.params[c]);
        }
        p.series.push_back(s);
      }
      p.key = r.groups.size() > 4 ? "off" : "";
      fig.panels.push_back(p);
    }
  }
  return fig;
}

// Abacus: the group fits (and each impact's) against the grouping parameter `by`, whose value
// per group is xs.
report::Figure abacus_figure(const UpscaleResult& r, const std::string& by,
                             const std::vector<double>& xs) {
  const auto& names = r.impacts.front().fit.names;
  const auto& calibrated = r.impacts.front().fit.calibrated;
  report::Figure fig;
  fig.title = "Abacus: equivalent parameters against " + by + " (" + r.shape + ")";
  fig.columns = static_cast<int>(calibrated.size());
  for (std::size_t c : calibrated) {
    report::Panel p;
    p.title = names[c];
    p.xlabel = by;
    p.ylabel = names[c];
    report::Series groups, impacts;
    groups.title = "group fit (near-optimal interval)";
    groups.style = "errorbars";
    impacts.title = "per impact";
    impacts.style = "points";
    impacts.point_type = 6;
    for (std::size_t k = 0; k < r.groups.size(); ++k) {
      const auto& g = r.groups[k];
      groups.x.push_back(xs[k]);
      groups.y.push_back(g.population.params[c]);
      const auto it =
          std::find_if(g.population.intervals.begin(), g.population.intervals.end(),
                       [&](const fit::ParameterInterval& iv) { return iv.name == names[c]; });
      groups.ylo.push_back(it != g.population.intervals.end() ? it->lo : g.population.params[c]);
      groups.yhi.push_back(it != g.population.intervals.end() ? it->hi : g.population.params[c]);
      for (std::size_t i : g.members) {
        impacts.x.push_back(xs[k]);
        impacts.y.push_back(r.impacts[i].fit.params[c]);
      }
    }
    p.series = {groups, impacts};
    fig.panels.push_back(p);
  }
  return fig;
}

// The gap to the lab: ECDFs of V_out.
report::Figure vout_against_lab_figure(const UpscaleResult& r) {
  report::Figure fig;
  fig.title = "Reflected velocities: resolved impacts vs lab (" + r.shape + ")";
  const char* labels[3] = {"V_out^x [m/s]", "V_out^y [m/s]", "omega_out [rad/s]"};
  for (int c = 0; c < 3; ++c) {
    std::vector<double> dem, measured;
    for (const auto& im : r.set.impacts) dem.push_back(im.vout[c]);
    for (const auto& im : r.lab.impacts) measured.push_back(im.vout[c]);
    fig.panels.push_back(
        report::ecdf_panel(labels[c], labels[c],
                           {{"LIGGGHTS (" + std::to_string(dem.size()) + ")", dem},
                            {"lab (" + std::to_string(measured.size()) + ")", measured}}));
  }
  return fig;
}

// The gap to the lab: ECDFs of the parameters calibrated on both sides by one engine.
report::Figure parameters_against_lab_figure(const UpscaleResult& r) {
  const auto& names = r.impacts.front().fit.names;
  report::Figure fig;
  fig.title = "Equivalent contact parameters: resolved impacts vs lab releases, one engine (" +
              r.shape + ")";
  for (std::size_t c : r.impacts.front().fit.calibrated) {
    std::vector<double> dem, measured;
    for (const auto& u : r.impacts) dem.push_back(u.fit.params[c]);
    for (const auto& f : r.lab_fits) measured.push_back(f.params[c]);
    fig.panels.push_back(report::ecdf_panel(
        names[c], names[c],
        {{"LIGGGHTS, per impact (" + std::to_string(dem.size()) + ")", dem},
         {"lab, per release (" + std::to_string(measured.size()) + ")", measured}}));
  }
  return fig;
}

}  // namespace

std::vector<std::string> write_upscale_figures(const UpscaleResult& r, const std::string& dir) {
  std::vector<std::string> written;
  fs::create_directories(dir);
  if (r.impacts.empty()) return written;
  const auto emit = [&](const report::Figure& fig, const std::string& file) {
    const std::string path = (fs::path(dir) / file).string();
    report::render(fig, path);
    written.push_back(path);
  };
  emit(parameters_figure(r), "upscale_parameters.svg");
  for (const auto& by : r.by) {
    std::vector<double> xs;
    for (const auto& g : r.groups) xs.push_back(number_or_nan(g.grain.at(by)));
    if (std::none_of(xs.begin(), xs.end(), [](double v) { return std::isfinite(v); })) continue;
    std::string file = "upscale_abacus_" + by + ".svg";
    std::replace(file.begin(), file.end(), '.', '_');
    file.replace(file.size() - 4, 4, ".svg");
    emit(abacus_figure(r, by, xs), file);
  }
  if (!r.lab.impacts.empty()) emit(vout_against_lab_figure(r), "upscale_vs_lab.svg");
  if (!r.lab_fits.empty()) emit(parameters_against_lab_figure(r), "upscale_parameters_vs_lab.svg");
  // The campaign's picture (/dem/snapshot), when it has one.
  if (const auto snap = read_snapshot(r.source)) {
    const std::string path = (fs::path(dir) / "impact_picture.png").string();
    report::render(report::impact_picture(*snap, fs::path(r.source).stem().string()), path);
    written.push_back(path);
  }
  return written;
}

}  // namespace ricochet::dem
