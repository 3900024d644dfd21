// The measurement floor of a set (assess.hpp, NoiseFloor): what Eq. 7's error would be if the
// model were exact and only the measurements' noise, and for releases of unknown orientation the
// spread over it, were left; and its terms on the error's scale.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.hpp"
#include "common/paths.hpp"
#include "diagnosis/assess.hpp"
#include "diagnosis/synth.hpp"

namespace ricochet::diagnosis {

void derive_floor_terms(NoiseFloor& f, const ImpactSet& set,
                        const std::array<bool, kObservables>& use, const AssessOptions& options) {
  const AssessOptions o = resolve_scale(set, options);
  const std::size_t n = f.variance.size();
  f.terms.assign(n, Obs{});
  f.per_release.assign(n, 0.0);
  f.term_mean = Obs{};
  f.sigma_mean = Obs{};
  for (std::size_t i = 0; i < n; ++i) {
    const Obs d = error_scale(set.impacts[i], o);
    double e = 0;
    for (int k = 0; k < kObservables; ++k) {
      f.terms[i][k] = use[k] ? f.variance[i][k] / (d[k] * d[k]) : 0.0;
      e += f.terms[i][k];
      f.term_mean[k] += f.terms[i][k] / static_cast<double>(n);
      f.sigma_mean[k] += use[k] ? std::sqrt(f.variance[i][k]) / static_cast<double>(n) : NAN;
    }
    f.per_release[i] = e;
  }
  f.value = mean_se(f.per_release);
  f.orientation_share = 0;
  for (std::size_t i = 0; i < n && i < f.orientation.size(); ++i) {
    const Obs d = error_scale(set.impacts[i], o);
    for (int k = 0; k < kObservables; ++k)
      if (use[k])
        f.orientation_share += f.orientation[i][k] / (d[k] * d[k]) / static_cast<double>(n);
  }
}

ReplicateScatter replicate_scatter(const ImpactSet& set) {
  const auto groups = replicate_groups(set);
  ReplicateScatter r;
  r.groups = groups.size();
  for (const auto& members : groups) r.dof += members.size() - 1;
  std::vector<double> x(set.size());
  for (int k = 0; k < kObservables; ++k) {
    for (std::size_t i = 0; i < set.size(); ++i) x[i] = measured_of(set.impacts[i])[k];
    r.variance[k] = pooled_variance(x, groups);
  }
  return r;
}

NoiseFloor noise_floor(const Model& model, const Shape& shape, std::span<const double> params,
                       const ImpactSet& set, const std::array<bool, kObservables>& use,
                       const AssessOptions& options) {
  const AssessOptions o = resolve_scale(set, options);
  NoiseFloor f;
  const std::size_t n = set.size();
  if (n == 0) throw std::invalid_argument("noise_floor: empty impact set");
  std::vector<Obs> d(n), m(n);
  for (std::size_t i = 0; i < n; ++i) {
    d[i] = error_scale(set.impacts[i], o);
    m[i] = measured_of(set.impacts[i]);
  }

  // Replicates: releases sharing a replicate label (a resolved campaign's replica beds and
  // positions: their measured V_in differ slightly, the experiment is the same), or releases
  // with identical incident state (and orientation); else another set's, when borrowed.
  const ReplicateScatter own = replicate_scatter(set);
  f.replicate_groups = own.groups;
  const bool borrowed = own.groups < 2 && o.borrowed_floor.has_value();
  const bool replicated = own.groups >= 2 || borrowed;
  const ReplicateScatter& pooled = borrowed ? *o.borrowed_floor : own;
  if (borrowed)
    for (int k = 0; k < kObservables; ++k)
      if (use[k] && !std::isfinite(pooled.variance[k]))
        throw InputError(pooled.source, 0, kObservableNames[k],
                         "no replicate group of this borrowed floor has it, and the compared "
                         "set's error uses it");
  // The sigma of each observable per release (physical units) before scaling.
  std::vector<Obs> var(n);
  // The prediction's spread over the unknown orientation (0 for discs and known alpha_in), at
  // the set's incident states: every source below gets its term.
  const bool sampled =
      !shape.is_disc() && std::any_of(set.impacts.begin(), set.impacts.end(),
                                      [](const Impact& im) { return !im.alpha_in.has_value(); });
  std::vector<ObsPrediction> base;
  if (sampled || !replicated) base = predict_observables(model, shape, params, set, o);
  f.orientation.assign(n, Obs{});
  bool any_spread = false;
  if (replicated) {
    f.source = borrowed ? "borrowed replicates" : "replicates";
    f.description =
        borrowed
            ? fmt::format(
                  "pooled within-group variance of {} groups of replicate releases of {}{} "
                  "({} degrees of freedom; the set has none of its own): the scatter of that "
                  "ground, taken as this set's",
                  pooled.groups, shown_path(pooled.source),
                  pooled.where.empty() ? "" : " (" + pooled.where + ")", pooled.dof)
            : fmt::format(
                  "pooled within-group variance of {} groups of replicate releases (same "
                  "replicate label or identical incident state) "
                  "({} degrees of freedom): measurement noise and release-to-release variability",
                  pooled.groups, pooled.dof);
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < kObservables; ++k) {
        if (!use[k]) continue;
        // The replicates' measured spread holds the true orientation's variance: only the
        // prediction's own spread is added (e_i counts it, (mean - m)^2 + spread^2).
        const double spread = sampled ? base[i].spread[k] : 0.0;
        any_spread = any_spread || spread > 0;
        f.orientation[i][k] = spread * spread;
        var[i][k] = pooled.variance[k] + f.orientation[i][k];
      }
    if (any_spread)
      f.description += ", plus the spread of the prediction over the unknown block orientation";
  } else {
    bool declared = true;
    for (const auto& im : set.impacts) declared = declared && im.sigma_vout.has_value();
    f.source = declared ? "declared" : "table1";
    // Feature uncertainties: extra columns written by synth (or a campaign), else defaults.
    auto extra_column = [&](const char* name) -> std::vector<double> {
      const auto it = std::find(set.extra_names.begin(), set.extra_names.end(), name);
      if (it == set.extra_names.end()) return {};
      return set.feature(name);
    };
    const std::vector<double> sh = extra_column(kSigmaPenetration);
    const std::vector<double> st = extra_column(kSigmaContactDuration);

    // V_in uncertainty propagated through the calibrated model: forward differences over a step
    // of the mean V_in uncertainty of each component.
    std::array<std::vector<ObsPrediction>, 3> shifted;
    Vel3 step{};
    for (int j = 0; j < 3; ++j) {
      for (const auto& im : set.impacts)
        step[j] += (im.sigma_vin ? (*im.sigma_vin)[j] : o.sigma_vin[j]) / static_cast<double>(n);
      if (!(step[j] > 0)) continue;
      ImpactSet moved = set;
      for (auto& im : moved.impacts) im.vin[j] += step[j];
      shifted[j] = predict_observables(model, shape, params, moved, o);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Impact& im = set.impacts[i];
      const Vel3 sin = im.sigma_vin ? *im.sigma_vin : o.sigma_vin;
      const Vel3 sout = im.sigma_vout ? *im.sigma_vout : o.fit.sigma;
      Obs meas_sd{sout[0], sout[1], sout[2],
                  !sh.empty() && std::isfinite(sh[i]) ? sh[i] : o.sigma_penetration_m,
                  !st.empty() && std::isfinite(st[i]) ? st[i] : o.sigma_contact_duration_s};
      for (int k = 0; k < kObservables; ++k) {
        if (!use[k]) continue;
        double prop = 0;
        for (int j = 0; j < 3; ++j) {
          if (shifted[j].empty()) continue;
          const double jac = (shifted[j][i].value[k] - base[i].value[k]) / step[j];
          if (std::isfinite(jac)) prop += jac * jac * sin[j] * sin[j];
        }
        const double spread = base[i].spread[k];
        any_spread = any_spread || spread > 0;
        // The truth's orientation and the prediction's are both unknown: the expected
        // error of the true model counts the spread twice (once for each).
        f.orientation[i][k] = 2.0 * spread * spread;
        var[i][k] = meas_sd[k] * meas_sd[k] + prop + f.orientation[i][k];
      }
    }
    f.description =
        (declared
             ? std::string("declared measurement uncertainties (sigma columns)")
             : fmt::format("the paper's Table 1 operator scale (V_out {:g} m/s, {:g} m/s, "
                           "{:g} rad/s; V_in {:g} m/s, {:g} m/s, {:g} rad/s)",
                           fit::LabNoise::vout[0], fit::LabNoise::vout[1], fit::LabNoise::vout[2],
                           fit::LabNoise::vin[0], fit::LabNoise::vin[1], fit::LabNoise::vin[2])) +
        ", plus the V_in uncertainty propagated through the calibrated model" +
        (any_spread ? ", plus the spread of the prediction over the unknown block orientation"
                    : "");
  }

  f.variance = var;
  derive_floor_terms(f, set, use, o);

  // Nearest-neighbour cross-check in standardised incident state (and orientation).
  if (n >= 2) {
    std::vector<std::array<double, 4>> x(n);
    std::array<double, 4> sd{};
    const bool alpha = std::all_of(set.impacts.begin(), set.impacts.end(),
                                   [](const Impact& im) { return im.alpha_in.has_value(); });
    for (int c = 0; c < 4; ++c) {
      if (c == 3 && !alpha) break;
      double mean = 0, sq = 0;
      for (std::size_t i = 0; i < n; ++i) {
        x[i][c] = c < 3 ? set.impacts[i].vin[c] : *set.impacts[i].alpha_in;
        mean += x[i][c] / static_cast<double>(n);
      }
      for (std::size_t i = 0; i < n; ++i) sq += (x[i][c] - mean) * (x[i][c] - mean);
      sd[c] = std::sqrt(sq / static_cast<double>(n - 1));
    }
    double total = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double best = INFINITY;
      std::size_t bj = i;
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        double dist = 0;
        for (int c = 0; c < 4; ++c)
          if (sd[c] > 0) dist += std::pow((x[i][c] - x[j][c]) / sd[c], 2);
        if (dist < best) best = dist, bj = j;
      }
      double e = 0;
      for (int k = 0; k < kObservables; ++k)
        if (use[k]) e += std::pow((m[i][k] - m[bj][k]) / d[i][k], 2);
      // A difference of two independent measurements has twice the variance of one.
      total += 0.5 * e / static_cast<double>(n);
    }
    f.nearest_neighbour = total;
  }
  return f;
}

}  // namespace ricochet::diagnosis
