#include "stats/lab_gap.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace ricochet::stats {
namespace {

constexpr std::array<const char*, 3> kOut = {"vout_x", "vout_y", "wout"};
constexpr std::array<const char*, 3> kIn = {"vin_x", "vin_y", "win"};

std::vector<double> subset(std::span<const double> x, const std::vector<bool>& keep) {
  std::vector<double> out;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (keep[i]) out.push_back(x[i]);
  return out;
}

std::vector<double> exit_slip(const ImpactSet& set, double radius_m) {
  std::vector<double> s;
  for (const auto& im : set.impacts) s.push_back(im.vout[kVx] + im.vout[kW] * radius_m);
  return s;
}

}  // namespace

ComponentGap component_gap(const std::string& name, std::span<const double> model,
                           std::span<const double> measured, const std::vector<bool>& core,
                           const std::optional<NoiseModel>& noise) {
  if (!core.empty() && core.size() != measured.size())
    throw std::invalid_argument("component_gap: the core mask differs in length from the data");
  ComponentGap g;
  g.name = name;
  g.model = summarize(model);
  g.measured = summarize(measured);
  g.ks = ks_two_sample(model, measured);
  g.model_robust = robust_summarize(model);
  g.measured_robust = robust_summarize(measured);
  if (noise) {
    g.noisy = ks_with_measurement_noise(model, measured, noise->sigma, noise->draws, noise->seed);
    g.noise_seed = noise->seed;
  }
  const bool some_out = std::find(core.begin(), core.end(), false) != core.end();
  if (some_out) {
    const std::vector<double> kept = subset(measured, core);
    g.measured_core = summarize(kept);
    if (!kept.empty()) g.ks_core = ks_two_sample(model, kept);
  }
  return g;
}

GrossErrors gross_errors_of(const ImpactSet& set) {
  std::vector<std::vector<double>> columns;
  std::vector<std::string> names;
  for (const auto& list : {kIn, kOut})
    for (const char* c : list) {
      columns.push_back(set.feature(c));
      names.emplace_back(c);
    }
  return flag_gross_errors(columns, names);
}

ImpactSet without_gross_errors(const ImpactSet& set, std::vector<std::string>* dropped) {
  const GrossErrors g = gross_errors_of(set);
  ImpactSet out = set;
  out.impacts.clear();
  std::string ids;
  for (std::size_t i = 0; i < set.size(); ++i) {
    if (!g.flagged[i]) {
      out.impacts.push_back(set.impacts[i]);
      continue;
    }
    ids += (ids.empty() ? "" : ", ") + set.impacts[i].id + " (" + g.why[i] + ")";
    if (dropped) dropped->push_back(set.impacts[i].id);
  }
  if (!ids.empty()) out.comments.push_back("without its gross errors (|modified z| > 3.5): " + ids);
  return out;
}

LabGap lab_gap(const ImpactSet& model, const ImpactSet& measured, const LabGapOptions& o) {
  if (model.empty() || measured.empty())
    throw std::invalid_argument("lab_gap: the model or the measured set is empty");
  LabGap gap;
  std::vector<std::vector<double>> columns;
  for (const char* c : kIn) columns.push_back(measured.feature(c));
  for (const char* c : kOut) columns.push_back(measured.feature(c));
  gap.measured_gross_errors = gross_errors_of(measured);
  std::vector<bool> core;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    core.push_back(!gap.measured_gross_errors.flagged[i]);
    if (!core.back()) gap.flagged_ids.push_back(measured.impacts[i].id);
  }

  for (std::size_t k = 0; k < 3; ++k) {
    std::optional<NoiseModel> noise;
    if (o.noise_sigma) noise = NoiseModel{(*o.noise_sigma)[k], o.noise_draws, o.seed};
    gap.components.push_back(
        component_gap(kOut[k], model.feature(kOut[k]), columns[3 + k], core, noise));
  }
  if (std::isfinite(o.disc_radius_m))
    gap.components.push_back(component_gap("slip_out", exit_slip(model, o.disc_radius_m),
                                           exit_slip(measured, o.disc_radius_m), core));

  std::array<double, 3> p{};
  for (std::size_t k = 0; k < 3; ++k) {
    // On the releases the gross-error rule keeps: a wild value sets a slope as it sets a mean.
    gap.response[k] = compare_responses(model.feature(kIn[k]), model.feature(kOut[k]),
                                        subset(columns[k], core), subset(columns[3 + k], core));
    p[k] = gap.response[k].p_value;
  }
  const std::vector<double> adjusted = holm_adjust(p);
  for (std::size_t k = 0; k < 3; ++k) gap.response_p_holm[k] = adjusted[k];
  return gap;
}

nlohmann::json to_json(const ComponentGap& g) {
  nlohmann::json j = {{"dem_mean", g.model.mean},
                      {"dem_std", g.model.std},
                      {"lab_mean", g.measured.mean},
                      {"lab_std", g.measured.std},
                      {"difference", g.model.mean - g.measured.mean},
                      {"difference_in_lab_std", (g.model.mean - g.measured.mean) / g.measured.std},
                      {"ks_statistic", g.ks.statistic},
                      {"ks_p_value", g.ks.p_value}};
  j["robust"] = {{"dem_median", g.model_robust.median},
                 {"dem_mad_sd", g.model_robust.mad_sd},
                 {"lab_median", g.measured_robust.median},
                 {"lab_mad_sd", g.measured_robust.mad_sd},
                 {"difference_in_lab_mad_sd",
                  (g.model_robust.median - g.measured_robust.median) / g.measured_robust.mad_sd}};
  if (g.measured_core && g.ks_core)
    j["lab_core"] = {
        {"n", g.measured_core->n},
        {"mean", g.measured_core->mean},
        {"std", g.measured_core->std},
        {"difference_in_core_std", (g.model.mean - g.measured_core->mean) / g.measured_core->std},
        {"ks_statistic", g.ks_core->statistic},
        {"ks_p_value", g.ks_core->p_value}};
  if (g.noisy)
    j["ks_with_lab_noise"] = {
        {"sigma", g.noisy->sigma}, {"draws", g.noisy->draws},
        {"seed", g.noise_seed},    {"median_p", g.noisy->median_p},
        {"p10", g.noisy->p10},     {"share_p_above_0.05", g.noisy->share_p_above_005}};
  return j;
}

nlohmann::json checks_json(const LabGap& gap) {
  nlohmann::json flagged = nlohmann::json::array();
  for (std::size_t i = 0, n = 0; i < gap.measured_gross_errors.flagged.size(); ++i)
    if (gap.measured_gross_errors.flagged[i])
      flagged.push_back({{"id", gap.flagged_ids[n++]}, {"why", gap.measured_gross_errors.why[i]}});
  nlohmann::json response;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& r = gap.response[k];
    response[kComponentNames[k]] = {
        {"slope_model", r.slope_model},  {"se_model", r.se_model},
        {"slope_lab", r.slope_measured}, {"se_lab", r.se_measured},
        {"reliability", r.reliability},  {"r_model", r.r_model},
        {"r_lab", r.r_measured},         {"n_model", r.n_model},
        {"n_lab", r.n_measured},         {"t", r.t},
        {"p_value", r.p_value},          {"p_holm", gap.response_p_holm[k]}};
  }
  return {{"lab_gross_errors", flagged}, {"lab_response", response}};
}

std::string to_text(const ComponentGap& g) {
  std::string s = fmt::format(
      "  {}: resolved {:.3f} +- {:.3f}, lab {:.3f} +- {:.3f}, gap {:+.3f} ({:+.1f} lab std), "
      "KS D = {:.2f}, p = {:.2g}\n",
      g.name, g.model.mean, g.model.std, g.measured.mean, g.measured.std,
      g.model.mean - g.measured.mean, (g.model.mean - g.measured.mean) / g.measured.std,
      g.ks.statistic, g.ks.p_value);
  s += fmt::format(
      "    robust: resolved median {:.3f} (MAD sd {:.3f}), lab median {:.3f} (MAD sd "
      "{:.3f}), gap {:+.1f} lab MAD sd\n",
      g.model_robust.median, g.model_robust.mad_sd, g.measured_robust.median,
      g.measured_robust.mad_sd,
      (g.model_robust.median - g.measured_robust.median) / g.measured_robust.mad_sd);
  if (g.measured_core && g.ks_core)
    s += fmt::format(
        "    lab without its gross errors ({} releases): {:.3f} +- {:.3f}, gap "
        "{:+.1f} std, KS D = {:.2f}, p = {:.2g}\n",
        g.measured_core->n, g.measured_core->mean, g.measured_core->std,
        (g.model.mean - g.measured_core->mean) / g.measured_core->std, g.ks_core->statistic,
        g.ks_core->p_value);
  if (g.noisy)
    s += fmt::format(
        "    with the lab's noise (sd {:g}) added to the resolved values, {} draws: KS p median "
        "{:.2g}, 10th percentile {:.2g}, p > 0.05 in {:.0f} % of draws\n",
        g.noisy->sigma, g.noisy->draws, g.noisy->median_p, g.noisy->p10,
        100.0 * g.noisy->share_p_above_005);
  return s;
}

std::string to_text(const LabGap& gap) {
  std::string s;
  for (const auto& g : gap.components) s += to_text(g);
  std::string ids;
  for (const auto& id : gap.flagged_ids) ids += (ids.empty() ? "" : ", ") + id;
  s += fmt::format("  lab gross errors (|modified z| > {}, the lab alone): {}\n",
                   kGrossErrorThreshold, ids.empty() ? "none" : ids);
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& r = gap.response[k];
    s += fmt::format(
        "  response of {} to {}: slope resolved {:+.2f} +- {:.2f}, lab {:+.2f} +- "
        "{:.2f} (reliability of the lab's {} {:.2f}), t {:.1f}, p {:.2g} (Holm over "
        "3: {:.2g})\n",
        kOut[k], kIn[k], r.slope_model, r.se_model, r.slope_measured, r.se_measured, kIn[k],
        r.reliability, r.t, r.p_value, gap.response_p_holm[k]);
  }
  return s;
}

}  // namespace ricochet::stats
