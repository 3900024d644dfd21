#include "stats/robust.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "common/nan.hpp"
#include "stats/median.hpp"
#include "stats/stats.hpp"

namespace ricochet::stats {
namespace {

// Median and raw MAD (unscaled) of the finite values.
std::pair<double, double> median_and_mad(std::span<const double> x) {
  std::vector<double> v;
  for (double a : x)
    if (!std::isnan(a)) v.push_back(a);
  const double med = median(v);
  for (double& a : v) a = std::abs(a - med);
  return {med, median(std::move(v))};
}

// Least-squares slope of y on x (NaN pairs skipped) and its standard error,
// se^2 = s_res^2 / sum (x - mean x)^2 with s_res^2 = RSS / (n - 2).
struct Slope {
  double b = kNaN, se = kNaN;
  std::size_t n = 0;
};
Slope ols_slope(std::span<const double> x, std::span<const double> y) {
  std::vector<double> vx, vy;
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i)
    if (!std::isnan(x[i]) && !std::isnan(y[i])) {
      vx.push_back(x[i]);
      vy.push_back(y[i]);
    }
  Slope s;
  s.n = vx.size();
  if (s.n < 3) return s;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < s.n; ++i) mx += vx[i], my += vy[i];
  mx /= static_cast<double>(s.n);
  my /= static_cast<double>(s.n);
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < s.n; ++i) {
    sxx += (vx[i] - mx) * (vx[i] - mx);
    sxy += (vx[i] - mx) * (vy[i] - my);
  }
  if (!(sxx > 0)) return s;
  s.b = sxy / sxx;
  double rss = 0;
  for (std::size_t i = 0; i < s.n; ++i) {
    const double e = vy[i] - my - s.b * (vx[i] - mx);
    rss += e * e;
  }
  s.se = std::sqrt(rss / static_cast<double>(s.n - 2) / sxx);
  return s;
}

}  // namespace

RobustSummary robust_summarize(std::span<const double> x) {
  RobustSummary s;
  for (double a : x) s.n += std::isnan(a) ? 0 : 1;
  const auto [med, mad] = median_and_mad(x);
  s.median = med;
  // 1.4826 = 1 / Phi^-1(3/4): the MAD of a normal sample is 0.6745 sd.
  s.mad_sd = 1.4826 * mad;
  return s;
}

std::vector<double> modified_z_scores(std::span<const double> x) {
  const auto [med, mad] = median_and_mad(x);
  std::vector<double> z(x.size(), kNaN);
  if (!(mad > 0)) return z;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!std::isnan(x[i])) z[i] = 0.6745 * (x[i] - med) / mad;
  return z;
}

GrossErrors flag_gross_errors(std::span<const std::vector<double>> columns,
                              std::span<const std::string> names, double threshold) {
  if (columns.size() != names.size())
    throw std::invalid_argument("flag_gross_errors: columns and names differ in count");
  if (!(threshold > 0)) throw std::invalid_argument("flag_gross_errors: threshold must be > 0");
  const std::size_t rows = columns.empty() ? 0 : columns.front().size();
  GrossErrors g;
  g.flagged.assign(rows, false);
  g.why.assign(rows, "");
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c].size() != rows)
      throw std::invalid_argument("flag_gross_errors: column '" + names[c] +
                                  "' differs in length from the first");
    const std::vector<double> z = modified_z_scores(columns[c]);
    for (std::size_t i = 0; i < rows; ++i) {
      if (!(std::abs(z[i]) > threshold)) continue;
      g.flagged[i] = true;
      char buf[64];
      std::snprintf(buf, sizeof buf, " (M = %+.1f)", z[i]);
      g.why[i] += (g.why[i].empty() ? "" : ", ") + names[c] + buf;
    }
  }
  g.count = static_cast<std::size_t>(std::count(g.flagged.begin(), g.flagged.end(), true));
  return g;
}

ResponseCheck compare_responses(std::span<const double> model_in, std::span<const double> model_out,
                                std::span<const double> measured_in,
                                std::span<const double> measured_out) {
  const Slope m = ols_slope(model_in, model_out);
  const Slope d = ols_slope(measured_in, measured_out);
  ResponseCheck r;
  r.slope_model = m.b;
  r.se_model = m.se;
  r.slope_measured = d.b;
  r.se_measured = d.se;
  r.n_model = m.n;
  r.n_measured = d.n;
  r.r_model = pearson(model_in, model_out).r;
  r.r_measured = pearson(measured_in, measured_out).r;
  if (m.n < 4 || d.n < 4 || !std::isfinite(m.b) || !std::isfinite(d.b) || m.b == 0) {
    r.reliability = r.t = r.p_value = kNaN;
    return r;
  }
  r.reliability = d.b / m.b;
  const double se = std::hypot(m.se, d.se);
  r.t = (m.b - d.b) / se;
  r.p_value = 2.0 * student_t_upper_tail(std::abs(r.t), static_cast<double>(d.n - 2));
  return r;
}

}  // namespace ricochet::stats
