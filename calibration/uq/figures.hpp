// SVG figures of the calibration and uncertainty analyses (gnuplot via report/plot.hpp), in the
// spirit of the paper's Figs. 15-18.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fit/fit.hpp"
#include "impact/impact_set.hpp"
#include "uq/montecarlo.hpp"
#include "uq/sobol.hpp"

namespace ricochet::uq {

/// Fig. 15: for each calibrated parameter, the ECDF of the per-release values, the ECDFs of the
/// near-optimal interval ends (where intervals were computed), the CDF of the given uniform
/// range (e.g. paper_ranges()) and of a distribution fitted to the values.
void figure_parameter_cdfs(const std::vector<fit::ReleaseFit>& fits,
                           const std::map<std::string, std::pair<double, double>>& ranges,
                           const std::string& svg_path);

/// Identifiability: per calibrated parameter, each release's value and near-optimal interval
/// (error bars; an interval reaching a bound means that side is not identified).
void figure_intervals(const std::vector<fit::ReleaseFit>& fits, const std::string& svg_path);

/// Measured versus simulated reflected velocity at the optimum, per component, with the 1:1 line.
void figure_fit_quality(const std::vector<fit::ReleaseFit>& fits, const std::string& svg_path);

/// Fig. 16: CDFs of the reflected velocities (vx, vy, w) of the Monte Carlo and of the
/// measurements (optional), one panel per component; `extra` adds more simulated sets.
void figure_reflected_cdfs(
    const MonteCarloResult& mc, const ImpactSet* measured, const std::string& svg_path,
    const std::string& label = "Monte Carlo",
    const std::vector<std::pair<std::string, const MonteCarloResult*>>& extra = {});

/// Figs. 17-18: first-order, total and second-order indices per output with their intervals.
void figure_sobol(const SobolResult& result, const std::string& svg_path);

}  // namespace ricochet::uq
