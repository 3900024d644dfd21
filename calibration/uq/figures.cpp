#include "uq/figures.hpp"

#include <algorithm>
#include <cmath>

#include "report/plot.hpp"
#include "uq/distribution.hpp"

namespace ricochet::uq {
namespace {

using report::Figure;
using report::Panel;
using report::Series;
namespace colour = report::colour;

std::vector<std::string> calibrated_names(const std::vector<fit::ReleaseFit>& fits) {
  std::vector<std::string> names;
  for (const auto& f : fits) {
    if (f.id.empty()) continue;
    for (std::size_t i : f.calibrated) names.push_back(f.names[i]);
    break;
  }
  return names;
}

// CDF of a distribution on a grid spanning [lo, hi].
Series cdf_series(const std::string& title, const Distribution& d, double lo, double hi,
                  const std::string& color) {
  Series s;
  s.title = title;
  s.color = color;
  for (int k = 0; k <= 200; ++k) {
    const double x = lo + (hi - lo) * k / 200.0;
    s.x.push_back(x);
    s.y.push_back(d.cdf(x));
  }
  return s;
}

int columns_for(std::size_t panels) {
  return static_cast<int>(std::min<std::size_t>(panels, 3));
}

}  // namespace

void figure_parameter_cdfs(const std::vector<fit::ReleaseFit>& fits,
                           const std::map<std::string, std::pair<double, double>>& ranges,
                           const std::string& svg_path) {
  Figure fig;
  fig.title = "Per-release calibrated parameters (cf. Garcia et al. 2020, Fig. 15)";
  for (const auto& name : calibrated_names(fits)) {
    std::vector<double> values, los, his;
    double blo = 0, bhi = 1;
    for (const auto& f : fits) {
      if (f.id.empty()) continue;
      values.push_back(f.value(name));
      if (const fit::ParameterInterval* iv = f.interval(name)) {
        los.push_back(iv->lo);
        his.push_back(iv->hi);
        if (std::isfinite(iv->bound_lo)) blo = iv->bound_lo, bhi = iv->bound_hi;
      }
    }
    std::vector<std::pair<std::string, std::vector<double>>> samples = {
        {"calibrated values", values}};
    if (!los.empty()) {
      samples.push_back({"interval lower ends", los});
      samples.push_back({"interval upper ends", his});
    }
    Panel p = report::ecdf_panel(name, name, samples);
    double lo = *std::min_element(values.begin(), values.end());
    double hi = *std::max_element(values.begin(), values.end());
    if (!his.empty()) hi = std::max(hi, *std::max_element(his.begin(), his.end()));
    if (!los.empty()) lo = std::min(lo, *std::min_element(los.begin(), los.end()));
    const auto r = ranges.find(name);
    if (r != ranges.end()) {
      lo = std::min(lo, r->second.first);
      hi = std::max(hi, r->second.second);
      p.series.push_back(cdf_series("uniform [" + std::to_string(r->second.first).substr(0, 4) +
                                        ", " + std::to_string(r->second.second).substr(0, 4) + "]",
                                    Distribution::uniform(r->second.first, r->second.second), lo,
                                    hi, colour::kBlack));
    }
    try {
      const Distribution d = Distribution::fitted(values, blo, bhi);
      // The full description (family and parameters) is in the JSON and HDF5 outputs; the
      // legend stays short.
      p.series.push_back(cdf_series("fitted (best family by BIC)", d, lo, hi, colour::kGrey));
    } catch (const std::exception&) {
      // Fewer than 3 distinct values: nothing to fit.
    }
    p.ylabel = "cumulative frequency";
    fig.panels.push_back(std::move(p));
  }
  if (fig.panels.empty()) return;
  fig.columns = columns_for(fig.panels.size());
  fig.width_px = 450 * fig.columns;
  fig.height_px = 420;
  report::render(fig, svg_path);
}

void figure_intervals(const std::vector<fit::ReleaseFit>& fits, const std::string& svg_path) {
  Figure fig;
  fig.title = "Near-optimal intervals per release (Eq. 7 within the noise threshold)";
  for (const auto& name : calibrated_names(fits)) {
    Series pts, bars;
    pts.title = "optimum";
    pts.style = "points";
    bars.title = "near-optimal interval";
    bars.style = "errorbars";
    bars.point_type = 1;
    double blo = NAN, bhi = NAN;
    int k = 0;
    for (const auto& f : fits) {
      if (f.id.empty()) continue;
      ++k;
      pts.x.push_back(k);
      pts.y.push_back(f.value(name));
      if (const fit::ParameterInterval* iv = f.interval(name)) {
        bars.x.push_back(k);
        bars.y.push_back(0.5 * (iv->lo + iv->hi));
        bars.ylo.push_back(iv->lo);
        bars.yhi.push_back(iv->hi);
        blo = iv->bound_lo;
        bhi = iv->bound_hi;
      }
    }
    Panel p;
    p.title = name;
    p.xlabel = "release (table order)";
    p.ylabel = name;
    if (!bars.x.empty()) p.series.push_back(bars);
    p.series.push_back(pts);
    if (std::isfinite(blo)) {
      p.ymin = blo;
      p.ymax = bhi;
    }
    p.key = "";  // the default: under the plot, never over data
    fig.panels.push_back(std::move(p));
  }
  if (fig.panels.empty()) return;
  fig.columns = columns_for(fig.panels.size());
  fig.width_px = 450 * fig.columns;
  fig.height_px = 420;
  report::render(fig, svg_path);
}

void figure_fit_quality(const std::vector<fit::ReleaseFit>& fits, const std::string& svg_path) {
  Figure fig;
  fig.title = "Reflected velocity: simulated at the optimum versus measured";
  const char* labels[3] = {"V_out^x [m/s]", "V_out^y [m/s]", "omega_out [rad/s]"};
  for (int k = 0; k < 3; ++k) {
    Series s, line;
    s.title = "releases";
    s.style = "points";
    double lo = 1e300, hi = -1e300;
    for (const auto& f : fits) {
      if (f.id.empty()) continue;
      s.x.push_back(f.measured[k]);
      s.y.push_back(f.simulated[k]);
      lo = std::min({lo, f.measured[k], f.simulated[k]});
      hi = std::max({hi, f.measured[k], f.simulated[k]});
    }
    line.title = "1:1";
    line.x = {lo, hi};
    line.y = {lo, hi};
    line.color = colour::kBlack;
    Panel p;
    p.title = labels[k];
    p.xlabel = std::string("measured ") + labels[k];
    p.ylabel = std::string("simulated ") + labels[k];
    p.series = {s, line};
    p.key = "";  // the default: under the plot, never over data
    fig.panels.push_back(std::move(p));
  }
  report::render(fig, svg_path);
}

void figure_reflected_cdfs(
    const MonteCarloResult& mc, const ImpactSet* measured, const std::string& svg_path,
    const std::string& label,
    const std::vector<std::pair<std::string, const MonteCarloResult*>>& extra) {
  Figure fig;
  fig.title =
      "Reflected velocities: Monte Carlo versus measurements (cf. Garcia et al. 2020, Fig. 16)";
  const char* labels[3] = {"V_out^x [m/s]", "V_out^y [m/s]", "omega_out [rad/s]"};
  const char* features[3] = {"vout_x", "vout_y", "wout"};
  for (int k = 0; k < 3; ++k) {
    std::vector<std::pair<std::string, std::vector<double>>> samples;
    samples.push_back(
        {label + " (" + std::to_string(mc.component(k).size()) + " runs)", mc.component(k)});
    for (const auto& [name, other] : extra) samples.push_back({name, other->component(k)});
    if (measured)
      samples.push_back(
          {"measured (" + std::to_string(measured->size()) + ")", measured->feature(features[k])});
    Panel p = report::ecdf_panel(labels[k], labels[k], samples);
    p.ylabel = "cumulative frequency";
    fig.panels.push_back(std::move(p));
  }
  fig.width_px = 1350;
  fig.height_px = 420;
  report::render(fig, svg_path);
}

void figure_sobol(const SobolResult& r, const std::string& svg_path) {
  Figure fig;
  fig.title = "Sobol indices (" + r.estimator + ", N = " + std::to_string(r.base_size) + ", " +
              std::to_string(static_cast<int>(std::lround(100 * r.confidence))) +
              "% bootstrap intervals; cf. Garcia et al. 2020, Figs. 17-18)";
  const std::size_t d = r.inputs.size();
  std::string xlabel;
  for (std::size_t i = 0; i < d; ++i)
    xlabel += (i ? ", " : "") + std::to_string(i + 1) + " = " + r.inputs[i];
  for (std::size_t o = 0; o < r.outputs.size(); ++o) {
    Panel p;
    p.title = "output " + r.outputs[o];
    p.xlabel = "input (" + xlabel + ")";
    p.ylabel = "index";
    Series s1, st;
    s1.title = "first order";
    s1.style = "errorbars";
    st.title = "total";
    st.style = "errorbars";
    st.point_type = 5;
    for (std::size_t i = 0; i < d; ++i) {
      s1.x.push_back(static_cast<double>(i + 1) - 0.1);
      s1.y.push_back(r.first[o][i].value);
      s1.ylo.push_back(r.first[o][i].lo);
      s1.yhi.push_back(r.first[o][i].hi);
      st.x.push_back(static_cast<double>(i + 1) + 0.1);
      st.y.push_back(r.total[o][i].value);
      st.ylo.push_back(r.total[o][i].lo);
      st.yhi.push_back(r.total[o][i].hi);
    }
    p.series = {s1, st};
    p.xmin = 0.5;
    p.xmax = static_cast<double>(d) + 0.5;
    p.ymin = -0.2;
    p.ymax = 1.2;
    p.key = "";  // the default: under the plot, never over data
    fig.panels.push_back(std::move(p));
  }
  for (std::size_t o = 0; o < r.outputs.size(); ++o) {
    Panel p;
    p.title = "second order, output " + r.outputs[o];
    Series s2;
    s2.title = "S_ij";
    s2.style = "errorbars";
    std::string pairs;
    int k = 0;
    for (std::size_t i = 0; i < d; ++i)
      for (std::size_t j = i + 1; j < d; ++j) {
        ++k;
        s2.x.push_back(k);
        s2.y.push_back(r.second[o][i][j].value);
        s2.ylo.push_back(r.second[o][i][j].lo);
        s2.yhi.push_back(r.second[o][i][j].hi);
        pairs += (pairs.empty() ? "" : ", ") + std::to_string(k) + " = " + r.inputs[i] + "-" +
                 r.inputs[j];
      }
    p.xlabel = "pair (" + pairs + ")";
    p.ylabel = "index";
    p.series = {s2};
    p.xmin = 0.5;
    p.xmax = k + 0.5;
    p.key = "";  // the default: under the plot, never over data
    fig.panels.push_back(std::move(p));
  }
  fig.columns = static_cast<int>(r.outputs.size());
  fig.width_px = 450 * fig.columns;
  fig.height_px = 800;
  report::render(fig, svg_path);
}

}  // namespace ricochet::uq
