// The grain calibration's outputs (grain_calibration.hpp): its JSON document and its figures (the
// surrogate's leave-one-out check, the Sobol abacus, the curves through the calibrated point).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/json_number.hpp"
#include "grain_calibration.hpp"
#include "report/plot.hpp"

namespace ricochet::dem {

namespace {

const char* kComponent[3] = {"vout_x", "vout_y", "wout"};
const char* kLabel[3] = {"V_out^x [m/s]", "V_out^y [m/s]", "omega_out [rad/s]"};

}  // namespace

std::string grain_calibration_json(const GrainCalibrationResult& r) {
  using nlohmann::json;
  json j;
  j["source"] = r.source;
  j["parameters"] = r.parameters;
  j["lower"] = r.lower;
  j["upper"] = r.upper;
  j["deck_default"] = r.deck_default;
  j["design_points"] = r.points.size();
  j["failed_impacts"] = r.failed;
  j["replicate_sd"] = r.replicate_sd;
  json comp = json::object();
  for (int c = 0; c < 3; ++c) {
    json s = json::object();
    for (std::size_t k = 0; k < r.parameters.size(); ++k)
      s[r.parameters[k]] = {{"first", r.first[c][k]},
                            {"first_interval", {r.first_lo[c][k], r.first_hi[c][k]}},
                            {"total", r.total[c][k]},
                            {"total_interval", {r.total_lo[c][k], r.total_hi[c][k]}}};
    comp[kComponent[c]] = {
        {"q2_loo", r.q2[c]},
        {"rmse_loo", r.rmse_loo[c]},
        {"target_mean", r.target_mean[c]},
        {"target_sd", r.target_sd[c]},
        {"predicted_mean", r.best_mean[c]},
        {"predicted_sd", r.best_sd[c]},
        {"gap_in_target_sd", (r.best_mean[c] - r.target_mean[c]) / r.target_sd[c]},
        {"sobol", s}};
  }
  j["components"] = comp;
  json best = json::object();
  for (std::size_t k = 0; k < r.parameters.size(); ++k) best[r.parameters[k]] = r.best[k];
  j["calibrated"] = best;
  j["misfit"] = r.best_misfit;
  if (std::isfinite(r.best_solid_fraction))
    j["packing"] = {{"solid_fraction_band", r.solid_fraction_band},
                    {"calibrated_solid_fraction", r.best_solid_fraction},
                    {"calibrated_solid_fraction_sd", r.best_solid_fraction_sd},
                    {"q2_loo", r.solid_fraction_q2}};
  if (!r.grain_count_estimates.empty()) {
    json est = json::array();
    for (const auto& e : r.grain_count_estimates)
      est.push_back({{"geometry", e.geometry},
                     {"beds", e.beds},
                     {"references", e.references},
                     {"loo_max_abs_error", finite_or_null(e.loo_max_abs)}});
    j["packing_from_grain_count"] = est;
  }
  if (!r.rebound_points.empty()) {
    json pts = json::array();
    for (const auto& t : r.rebound_points)
      pts.push_back({{"x", t.x},
                     {"rebounds", t.rebounds},
                     {"counted", t.counted},
                     {"missed", t.missed},
                     {"loo", finite_or_null(t.loo)}});
    j["rebound_region"] = {{"threshold", r.rebound_threshold},
                           {"loo_agreement", finite_or_null(r.rebound_loo_agreement)},
                           {"box_fraction", finite_or_null(r.rebound_box_fraction)},
                           {"calibrated_rebound", finite_or_null(r.best_rebound)},
                           {"points", pts}};
  }
  j["admissible_fraction"] = r.admissible_fraction;
  j["acceptable_fraction"] = r.acceptable_fraction;
  j["target_impacts"] = r.target_n;
  json pts = json::array();
  for (const auto& p : r.points) {
    json q = {
        {"x", p.x}, {"mean", p.mean}, {"loo", p.loo}, {"replicas", p.replicas}, {"ids", p.ids}};
    if (std::isfinite(p.solid_fraction)) {
      q["solid_fraction"] = {p.solid_fraction, p.solid_fraction_loo};
      q["solid_fraction_source"] = p.solid_fraction_source;
    }
    pts.push_back(q);
  }
  j["points"] = pts;
  j["seconds"] = r.seconds;
  return j.dump();
}

std::vector<std::string> write_grain_calibration_figures(const GrainCalibrationResult& r,
                                                         const std::string& dir) {
  using report::Figure;
  using report::Panel;
  using report::Series;
  std::vector<std::string> files;
  const std::size_t d = r.parameters.size();
  namespace colour = report::colour;
  const char* palette[] = {colour::kBlue,          colour::kOrange,  colour::kBluishGreen,
                           colour::kReddishPurple, colour::kSkyBlue, colour::kVermillion,
                           colour::kGrey,          colour::kBlack};

  Figure sobol;
  sobol.title =
      "Sobol indices of the resolved V_out on the surrogate (first order: filled, total: open; 95 "
      "% bootstrap)";
  for (int c = 0; c < 3; ++c) {
    Panel p;
    p.title = kLabel[c] + fmt::format(" (LOO Q2 = {:.2f})", r.q2[c]);
    p.xlabel = "parameter";
    p.ylabel = "Sobol index";
    p.xmin = 0.5;
    p.xmax = static_cast<double>(d) + 0.5;
    p.ymin = -0.05;
    p.ymax = 1.05;
    p.key = "";  // the default: under the plot, never over data
    for (std::size_t k = 0; k < d; ++k) {
      const double x = static_cast<double>(k + 1);
      Series f{r.parameters[k],    {x - 0.12},         {r.first[c][k]}, "errorbars",
               {r.first_lo[c][k]}, {r.first_hi[c][k]}, palette[k % 8],  7};
      Series t{"",
               {x + 0.12},
               {r.total[c][k]},
               "errorbars",
               {r.total_lo[c][k]},
               {r.total_hi[c][k]},
               palette[k % 8],
               6};
      p.series.push_back(f);
      p.series.push_back(t);
    }
    sobol.panels.push_back(p);
  }
  files.push_back(dir + "/grains_sobol.svg");
  report::render(sobol, files.back());

  Figure loo;
  loo.title =
      "Surrogate validation: leave-one-out prediction against each design point's replica mean";
  for (int c = 0; c < 3; ++c) {
    Panel p;
    p.title = kLabel[c] + fmt::format(" Q2 = {:.2f}, RMSE = {:.3g}", r.q2[c], r.rmse_loo[c]);
    p.xlabel = "resolved (replica mean)";
    p.ylabel = "leave-one-out prediction";
    Series s{"design points", {}, {}, "points", {}, {}, palette[0], 7};
    double lo = 1e300, hi = -1e300;
    for (const auto& q : r.points) {
      s.x.push_back(q.mean[c]);
      s.y.push_back(q.loo[c]);
      lo = std::min({lo, q.mean[c], q.loo[c]});
      hi = std::max({hi, q.mean[c], q.loo[c]});
    }
    p.series.push_back(s);
    p.series.push_back(Series{"1:1", {lo, hi}, {lo, hi}, "lines", {}, {}, colour::kBlack, 7});
    p.key = "";  // the default: under the plot, never over data
    loo.panels.push_back(p);
  }
  files.push_back(dir + "/grains_loo.svg");
  report::render(loo, files.back());

  Figure abacus;
  abacus.title =
      "Abacus: surrogate V_out against each grain parameter through the calibrated point (mean +- "
      "2 sd; band: target mean +- 0.5 sd)";
  abacus.columns = static_cast<int>(d);
  abacus.width_px = 260 * static_cast<int>(d);
  abacus.height_px = 780;
  for (int c = 0; c < 3; ++c)
    for (std::size_t k = 0; k < d; ++k) {
      Panel p;
      p.xlabel = r.parameters[k];
      p.ylabel = kLabel[c];
      p.key = "off";
      Series m{"surrogate", r.grid[k], r.curve_mean[k][c], "lines", {}, {}, palette[0], 7};
      Series lo{"-2 sd", r.grid[k], {}, "lines", {}, {}, colour::kSkyBlue, 7};
      Series hi{"+2 sd", r.grid[k], {}, "lines", {}, {}, colour::kSkyBlue, 7};
      for (std::size_t i = 0; i < r.grid[k].size(); ++i) {
        lo.y.push_back(r.curve_mean[k][c][i] - 2 * r.curve_sd[k][c][i]);
        hi.y.push_back(r.curve_mean[k][c][i] + 2 * r.curve_sd[k][c][i]);
      }
      const double a = r.lower[k], b = r.upper[k];
      Series t1{"target",
                {a, b},
                {r.target_mean[c] - 0.5 * r.target_sd[c], r.target_mean[c] - 0.5 * r.target_sd[c]},
                "lines",
                {},
                {},
                colour::kVermillion,
                7};
      Series t2{"",
                {a, b},
                {r.target_mean[c] + 0.5 * r.target_sd[c], r.target_mean[c] + 0.5 * r.target_sd[c]},
                "lines",
                {},
                {},
                colour::kVermillion,
                7};
      Series at{"calibrated", {r.best[k]}, {r.best_mean[c]}, "points", {}, {}, colour::kBlack, 5};
      p.series = {lo, hi, m, t1, t2, at};
      abacus.panels.push_back(p);
    }
  files.push_back(dir + "/grains_abacus.svg");
  report::render(abacus, files.back());

  if (!r.curve_rebound.empty()) {
    Figure rebound;
    rebound.title = fmt::format(
        "Rebound region: indicator kriging of the design's rebounds through the calibrated point "
        "(searched where >= {}; points: each design point's rebound fraction, all parameters "
        "projected)",
        r.rebound_threshold);
    rebound.columns = static_cast<int>(d);
    rebound.width_px = 260 * static_cast<int>(d);
    rebound.height_px = 300;
    for (std::size_t k = 0; k < d; ++k) {
      Panel p;
      p.xlabel = r.parameters[k];
      p.ylabel = "P(rebound)";
      p.key = "off";
      Series pts{"design points", {}, {}, "points", {}, {}, colour::kGrey, 7};
      for (const auto& t : r.rebound_points) {
        pts.x.push_back(t.x[k]);
        pts.y.push_back(static_cast<double>(t.rebounds) / static_cast<double>(t.counted));
      }
      Series m{"indicator", r.grid[k], r.curve_rebound[k], "lines", {}, {}, palette[0], 7};
      Series th{"threshold",
                {r.lower[k], r.upper[k]},
                {r.rebound_threshold, r.rebound_threshold},
                "lines",
                {},
                {},
                colour::kVermillion,
                7};
      Series at{"calibrated", {r.best[k]}, {r.best_rebound}, "points", {}, {}, colour::kBlack, 5};
      p.series = {pts, m, th, at};
      rebound.panels.push_back(p);
    }
    files.push_back(dir + "/grains_rebound.svg");
    report::render(rebound, files.back());
  }
  return files;
}

}  // namespace ricochet::dem
