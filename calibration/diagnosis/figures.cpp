#include "diagnosis/figures.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <filesystem>

namespace ricochet::diagnosis {
namespace {

using report::Figure;
using report::Panel;
using report::Series;
namespace colour = report::colour;

// Physical scale of an observable in figures (penetration in mm, duration in ms).
double plot_scale(int k) {
  return k == kObsPenetration || k == kObsDuration ? 1e3 : 1.0;
}
std::string plot_unit(int k) {
  return k == kObsPenetration ? "mm" : k == kObsDuration ? "ms" : kObservableUnits[k];
}

Series points(std::string title, std::vector<double> x, std::vector<double> y,
              std::string color = "", int pt = 7) {
  Series s;
  s.title = std::move(title);
  s.x = std::move(x);
  s.y = std::move(y);
  s.style = "points";
  s.color = std::move(color);
  s.point_type = pt;
  return s;
}

Series line(std::string title, std::vector<double> x, std::vector<double> y,
            std::string color = "") {
  Series s;
  s.title = std::move(title);
  s.x = std::move(x);
  s.y = std::move(y);
  s.style = "lines";
  s.color = std::move(color);
  return s;
}

std::pair<double, double> range_of(const std::vector<double>& v) {
  double lo = INFINITY, hi = -INFINITY;
  for (double x : v)
    if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
  return {lo, hi};
}

int columns_for(std::size_t panels) {
  return static_cast<int>(std::min<std::size_t>(panels, 4));
}
int height_for(std::size_t panels, int per_row = 330) {
  const std::size_t rows = (panels + 3) / 4;
  return static_cast<int>(std::max<std::size_t>(1, rows)) * per_row;
}

// A figure of one panel per item in rows of up to four, each panel `panel_width_px` wide.
Figure grid_figure(std::string title, std::size_t panels, int panel_width_px, int panel_height_px) {
  Figure f;
  f.title = std::move(title);
  f.columns = columns_for(panels);
  f.width_px = panel_width_px * f.columns;
  f.height_px = height_for(panels, panel_height_px);
  return f;
}

// A figure of a fixed layout: `columns` panels in a row, width_px x height_px in all.
Figure fixed_figure(std::string title, int columns, int width_px, int height_px) {
  Figure f;
  f.title = std::move(title);
  f.columns = columns;
  f.width_px = width_px;
  f.height_px = height_px;
  return f;
}

// Measured values of observable k: held-out prediction plus residual, in plot units.
std::vector<double> measured(const Assessment& a, std::size_t n, int k) {
  std::vector<double> y;
  for (std::size_t i = 0; i < n; ++i)
    y.push_back((a.heldout_predictions[i].value[k] + a.heldout.residual[i][k]) * plot_scale(k));
  return y;
}
std::vector<double> predicted(const Assessment& a, std::size_t n, int k) {
  std::vector<double> x;
  for (std::size_t i = 0; i < n; ++i)
    x.push_back(a.heldout_predictions[i].value[k] * plot_scale(k));
  return x;
}

NamedFigure measured_against_predicted(const Assessment& a, std::size_t n,
                                       const std::vector<int>& used, const std::string& title) {
  Figure f = grid_figure(title + ": measured against held-out predicted", used.size(), 330, 340);
  for (int k : used) {
    const std::vector<double> x = predicted(a, n, k), y = measured(a, n, k);
    auto [lo1, hi1] = range_of(x);
    auto [lo2, hi2] = range_of(y);
    const double lo = std::min(lo1, lo2), hi = std::max(hi1, hi2);
    Panel p;
    p.title = kObservableLabels[k];
    p.xlabel = fmt::format("predicted [{}]", plot_unit(k));
    p.ylabel = fmt::format("measured [{}]", plot_unit(k));
    p.key = "";  // the default: under the plot, never over data
    p.series.push_back(points("releases", x, y, colour::kBlue));
    if (std::isfinite(lo)) p.series.push_back(line("1:1", {lo, hi}, {lo, hi}, colour::kGrey));
    f.panels.push_back(p);
  }
  return {"measured-vs-predicted",
          "Measured against held-out predicted values (each release predicted by a "
          "population fit that did not see it); the grey line is 1:1.",
          f};
}

NamedFigure distributions(const Baseline& b, std::size_t n, const std::vector<int>& used,
                          const std::string& title) {
  Figure f = grid_figure(title + ": measured and predicted distributions", used.size(), 330, 340);
  for (int k : used) {
    f.panels.push_back(report::ecdf_panel(
        fmt::format("{} (KS D = {:.2f}, p = {:.2g})", kObservableLabels[k], b.ks[k].statistic,
                    b.ks[k].p_value),
        fmt::format("{} [{}]", kObservableLabels[k], plot_unit(k)),
        {{"measured", measured(b.base, n, k)}, {"predicted (held-out)", predicted(b.base, n, k)}}));
  }
  return {"cdfs",
          "Empirical CDFs of the measured and held-out predicted values, with the "
          "two-sample Kolmogorov-Smirnov statistic and p-value.",
          f};
}

// Residuals of observable k against every impact feature.
NamedFigure residuals_against_features(const Baseline& b, std::size_t n, int k,
                                       const std::string& title) {
  Figure f = grid_figure(
      fmt::format("{}: {} residual (measured - held-out predicted) against impact features", title,
                  kObservableLabels[k]),
      b.features.size(), 300, 300);
  std::vector<double> y;
  for (std::size_t i = 0; i < n; ++i) y.push_back(b.base.heldout.residual[i][k] * plot_scale(k));
  for (const auto& feat : b.features) {
    Panel p;
    const Trend* t = find_trend(b.residual_trends, residual_quantity(k), feat.name);
    p.title = t && std::isfinite(t->r) ? fmt::format("r = {:.2f}, p = {:.2g}", t->r, t->p) : "";
    p.xlabel = feat.label;
    p.ylabel = fmt::format("residual [{}]", plot_unit(k));
    p.key = "off";
    p.series.push_back(points("releases", feat.values, y,
                              t && t->significant ? colour::kVermillion : colour::kBlue));
    auto [lo, hi] = range_of(feat.values);
    if (std::isfinite(lo)) p.series.push_back(line("zero", {lo, hi}, {0.0, 0.0}, colour::kGrey));
    f.panels.push_back(p);
  }
  return {std::string("residuals-") + kObservableNames[k],
          fmt::format("{} residuals against each impact feature; red panels show a "
                      "significant trend (Pearson p < 0.01), the strongest hint of "
                      "missing physics.",
                      kObservableLabels[k]),
          f};
}

// The per-release calibrated parameter `c` against every impact feature.
NamedFigure parameter_against_features(const Baseline& b, std::size_t n, std::size_t c,
                                       const std::string& title) {
  const std::string name = b.release_fits.front().names[c];
  Figure f =
      grid_figure(fmt::format("{}: per-release calibrated {} against impact features", title, name),
                  b.features.size(), 300, 300);
  for (const auto& feat : b.features) {
    std::vector<double> xi, yi, xn, yn;
    for (std::size_t i = 0; i < n; ++i) {
      const auto* iv = b.release_fits[i].interval(name);
      const bool ok = !iv || iv->status == fit::Identifiability::kIdentified;
      (ok ? xi : xn).push_back(feat.values[i]);
      (ok ? yi : yn).push_back(b.release_fits[i].params[c]);
    }
    const Trend* t = find_trend(b.parameter_trends, parameter_quantity(name), feat.name);
    Panel p;
    p.title = t && std::isfinite(t->r) ? fmt::format("r = {:.2f}, p = {:.2g}", t->r, t->p) : "";
    p.xlabel = feat.label;
    p.ylabel = name;
    p.key = "off";
    p.series.push_back(
        points("identified", xi, yi, t && t->significant ? colour::kVermillion : colour::kBlue));
    p.series.push_back(points("not identified", xn, yn, colour::kGrey, 6));
    f.panels.push_back(p);
  }
  return {"parameter-" + name,
          fmt::format("Per-release calibrated {} against each impact feature (filled: "
                      "identified; open grey: only bounded). A constant that drifts "
                      "with a feature absorbs missing physics.",
                      name),
          f};
}

// Held-out error against the noise floor, per release and per regime.
NamedFigure errors_per_release_and_regime(const Baseline& b, const ImpactSet& set,
                                          const std::string& title) {
  const std::size_t n = set.size();
  Figure f = fixed_figure(title + ": held-out error per release and per regime", 2, 1100, 380);
  Panel p1;
  p1.title = "per release (sorted by |V_in|)";
  p1.xlabel = "|V_in| [m/s]";
  p1.ylabel = "error (Eq. 7 and contact terms)";
  p1.key = "";  // the default: under the plot, never over data
  std::vector<double> x, e, fl;
  for (std::size_t i = 0; i < n; ++i) {
    x.push_back(std::hypot(set.impacts[i].vin[0], set.impacts[i].vin[1]));
    e.push_back(b.base.heldout.per_release[i]);
    fl.push_back(b.floor.per_release[i]);
  }
  p1.series.push_back(points("held-out error", x, e, colour::kVermillion));
  p1.series.push_back(points("noise floor", x, fl, colour::kBluishGreen, 6));
  Panel p2;
  p2.title = "per regime (mean +- 1 SE)";
  p2.xlabel = "regime (1 = slowest)";
  p2.ylabel = "mean error";
  p2.key = "";  // the default: under the plot, never over data
  Series s;
  s.title = "held-out error";
  s.style = "errorbars";
  s.color = colour::kVermillion;
  Series sf = s;
  sf.title = "noise floor";
  sf.color = colour::kBluishGreen;
  for (std::size_t r = 0; r < b.regimes.size(); ++r) {
    const auto& g = b.regimes[r];
    s.x.push_back(static_cast<double>(r + 1));
    s.y.push_back(g.heldout.mean);
    s.ylo.push_back(g.heldout.mean - g.heldout.se);
    s.yhi.push_back(g.heldout.mean + g.heldout.se);
    sf.x.push_back(static_cast<double>(r + 1) + 0.1);
    sf.y.push_back(g.floor.mean);
    sf.ylo.push_back(g.floor.mean - g.floor.se);
    sf.yhi.push_back(g.floor.mean + g.floor.se);
  }
  p2.series = {s, sf};
  p2.xmin = 0.5;
  p2.xmax = static_cast<double>(b.regimes.size()) + 0.6;
  p2.ymin = 0;
  f.panels = {p1, p2};
  return {"errors",
          "Held-out error per release and per regime (thirds of the releases by "
          "|V_in|) against the noise floor.",
          f};
}

}  // namespace

std::vector<NamedFigure> compare_figures(const Baseline& b, const ImpactSet& set,
                                         const std::string& title) {
  const std::size_t n = set.size();
  std::vector<int> used;
  for (int k = 0; k < kObservables; ++k)
    if (b.base.use[k]) used.push_back(k);
  std::vector<NamedFigure> out;
  out.push_back(measured_against_predicted(b.base, n, used, title));
  out.push_back(distributions(b, n, used, title));
  for (int k : used) out.push_back(residuals_against_features(b, n, k, title));
  if (!b.release_fits.empty())
    for (std::size_t c : b.release_fits.front().calibrated)
      out.push_back(parameter_against_features(b, n, c, title));
  out.push_back(errors_per_release_and_regime(b, set, title));
  return out;
}

std::vector<NamedFigure> diagnose_figures(const Diagnosis& d, const std::string& title) {
  Figure f =
      fixed_figure(title + ": held-out error with each candidate effect added", 1, 1100, 420);
  Panel p;
  p.xlabel = "0 = base model; 1, 2, ... = candidates in ranking order";
  p.ylabel = "held-out error (mean +- 1 SE)";
  p.key = "outside right top";  // beside the plot: it covered the last candidates
  Series base;
  base.title = "base model";
  base.style = "errorbars";
  base.color = colour::kBlue;
  const auto& b = d.baseline;
  base.x = {0.0};
  base.y = {b.base.heldout.error.mean};
  base.ylo = {b.base.heldout.error.mean - b.base.heldout.error.se};
  base.yhi = {b.base.heldout.error.mean + b.base.heldout.error.se};
  Series sup = base, uns = base;
  sup.title = "supported";
  sup.color = colour::kBluishGreen;
  uns.title = "not supported";
  uns.color = colour::kVermillion;
  sup.x.clear(), sup.y.clear(), sup.ylo.clear(), sup.yhi.clear();
  uns.x.clear(), uns.y.clear(), uns.ylo.clear(), uns.yhi.clear();
  std::string names;
  for (std::size_t i = 0; i < d.ranking.size(); ++i) {
    const auto& c = d.ranking[i];
    names += fmt::format("{}{}={}", names.empty() ? "" : ", ", i + 1, c.effect);
    if (!std::isfinite(c.heldout_error)) continue;
    Series& s = c.supported ? sup : uns;
    s.x.push_back(static_cast<double>(i + 1));
    s.y.push_back(c.heldout_error);
    s.ylo.push_back(c.heldout_error - c.heldout_se);
    s.yhi.push_back(c.heldout_error + c.heldout_se);
  }
  const double xmax = static_cast<double>(d.ranking.size()) + 0.5;
  // A class with no candidate is left out of the legend: "supported (no data)" read as a
  // supported candidate whose data were missing.
  p.series = {base};
  for (const Series* s : {&sup, &uns})
    if (!s->x.empty()) p.series.push_back(*s);
  p.series.push_back(
      line("noise floor", {-0.5, xmax}, {b.floor.value.mean, b.floor.value.mean}, colour::kBlack));
  p.series.push_back(line("adequacy threshold", {-0.5, xmax},
                          {b.adequacy.threshold, b.adequacy.threshold}, colour::kGrey));
  p.title = names;
  p.xmin = -0.5;
  p.xmax = xmax;
  p.ymin = 0;
  f.panels = {p};
  return {{"diagnosis",
           "Held-out error of the base model and of the base model with each candidate effect "
           "added and recalibrated; green: supported (the drop passes the corrected resampled "
           "t-test under Holm's family-wise control and exceeds the penalty for the added "
           "parameters).",
           f}};
}

NamedFigure lab_gap_figure(const ImpactSet& set, const ImpactSet& lab, const stats::LabGap& gap,
                           double disc_radius_m, const std::string& title) {
  std::vector<double> slip_set, slip_lab;
  for (const auto& im : set.impacts) slip_set.push_back(im.vout[kVx] + im.vout[kW] * disc_radius_m);
  for (const auto& im : lab.impacts) slip_lab.push_back(im.vout[kVx] + im.vout[kW] * disc_radius_m);
  const std::vector<std::pair<const char*, const char*>> quantities = {
      {"vout_x", "V_out^x [m/s]"},
      {"vout_y", "V_out^y [m/s]"},
      {"wout", "omega_out [rad/s]"},
      {"slip_out", "exit slip V_out^x + omega_out R [m/s]"}};
  Figure f = fixed_figure(title + " against the lab", 2, 1200, 900);
  for (const auto& [name, label] : quantities) {
    const bool slip = std::string(name) == "slip_out";
    if (slip && !std::isfinite(disc_radius_m)) continue;
    std::vector<double> a = slip ? slip_set : set.feature(name);
    std::vector<double> b = slip ? slip_lab : lab.feature(name);
    std::vector<double> core;
    for (std::size_t i = 0; i < b.size(); ++i)
      if (!gap.measured_gross_errors.flagged[i]) core.push_back(b[i]);
    std::vector<std::pair<std::string, std::vector<double>>> samples = {
        {fmt::format("this set ({})", a.size()), a}, {fmt::format("lab ({})", b.size()), b}};
    if (core.size() < b.size())
      samples.push_back({fmt::format("lab without gross errors ({})", core.size()), core});
    f.panels.push_back(report::ecdf_panel(label, label, samples));
  }
  return {"against-lab", "Cumulative distributions of the set's rebounds and the lab's.", f};
}

std::vector<NamedFigure> ladder_figures(const Ladder& l, const std::string& title) {
  Figure f = fixed_figure(title + ": the model ladder", 2, 1200, 560);
  Panel p1;
  p1.title = "error falling towards the noise floor";
  p1.xlabel = "rung (0 = base; each adds one effect)";
  p1.ylabel = "mean error";
  p1.key = "outside bottom center horizontal";  // under the plot, never over a rung
  Series ins, ho;
  ins.title = "in-sample";
  ins.style = "linespoints";
  ins.color = colour::kBlue;
  ho.title = "held-out (+- 1 SE)";
  ho.style = "errorbars";
  ho.color = colour::kVermillion;
  Series hol = ho;
  hol.title = "held-out";
  hol.style = "lines";
  std::string names;
  for (std::size_t r = 0; r < l.rungs.size(); ++r) {
    const auto& a = l.rungs[r].assessment;
    const double x = static_cast<double>(r);
    ins.x.push_back(x);
    ins.y.push_back(a.insample.error.mean);
    ho.x.push_back(x);
    ho.y.push_back(a.heldout.error.mean);
    ho.ylo.push_back(a.heldout.error.mean - a.heldout.error.se);
    ho.yhi.push_back(a.heldout.error.mean + a.heldout.error.se);
    hol.x.push_back(x);
    hol.y.push_back(a.heldout.error.mean);
    names += fmt::format("{}{}={}", names.empty() ? "" : ", ", r,
                         r == 0 ? std::string("base") : "+" + l.rungs[r].added);
  }
  const double xmax = static_cast<double>(l.rungs.size()) - 0.5;
  p1.series = {
      ins, ho, hol,
      line("noise floor", {-0.5, xmax}, {l.floor.value.mean, l.floor.value.mean}, colour::kBlack)};
  p1.xmin = -0.5;
  p1.xmax = xmax;
  p1.ymin = 0;
  p1.xlabel = names;
  Panel p2;
  p2.title = "held-out error per observable";
  p2.xlabel = "rung";
  p2.ylabel = "mean error term";
  p2.key = "outside bottom center horizontal";
  p2.logy = true;
  if (!l.rungs.empty()) {
    const auto& use = l.rungs.front().assessment.use;
    const char* colors[kObservables] = {colour::kBlue, colour::kOrange, colour::kBluishGreen,
                                        colour::kReddishPurple, colour::kBlack};
    for (int k = 0; k < kObservables; ++k) {
      if (!use[k]) continue;
      Series s;
      s.title = kObservableLabels[k];
      s.style = "linespoints";
      s.color = colors[k];
      Series fl = line(std::string("floor ") + kObservableLabels[k], {-0.5, xmax},
                       {l.floor.term_mean[k], l.floor.term_mean[k]}, colors[k]);
      for (std::size_t r = 0; r < l.rungs.size(); ++r) {
        s.x.push_back(static_cast<double>(r));
        s.y.push_back(l.rungs[r].assessment.heldout.term_mean[k]);
      }
      p2.series.push_back(s);
      p2.series.push_back(fl);
    }
  }
  p2.xmin = -0.5;
  p2.xmax = xmax;
  f.panels = {p1, p2};
  return {{"ladder",
           "Each rung adds one effect and is recalibrated; in-sample and held-out errors "
           "against the noise floor (left) and the held-out error per observable with its own "
           "floor (right, log scale).",
           f}};
}

std::vector<std::string> render_all(const std::vector<NamedFigure>& figures,
                                    const std::string& dir) {
  std::vector<std::string> paths;
  for (const auto& f : figures) {
    const std::string path = (std::filesystem::path(dir) / (f.stem + ".svg")).string();
    report::render(f.figure, path);
    paths.push_back(path);
  }
  return paths;
}

}  // namespace ricochet::diagnosis
