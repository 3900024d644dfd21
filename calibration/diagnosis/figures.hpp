// Figures of compare, diagnose and ladder (report/plot.hpp: gnuplot SVG). Each function builds
// a report::Figure; render_all() writes a set of them to a directory.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "diagnosis/diagnose.hpp"
#include "report/plot.hpp"
#include "stats/lab_gap.hpp"

namespace ricochet::diagnosis {

/// A figure with the file stem it is written under and a caption.
struct NamedFigure {
  std::string stem;     ///< e.g. "residuals-vy"
  std::string caption;  ///< one sentence for the report
  report::Figure figure;
};

/// compare: measured vs predicted per observable (held-out, 1:1 line); measured and predicted
/// CDFs with the KS statistic; held-out residuals against every feature (one figure per
/// observable); per-release calibrated parameters against every feature (identified releases
/// filled, others open); error per release and per regime against the noise floor.
std::vector<NamedFigure> compare_figures(const Baseline& b, const ImpactSet& set,
                                         const std::string& title);
/// A set against the lab (stats::lab_gap): ECDFs of V_out^x, V_out^y, omega_out (and the exit
/// slip of a disc) of the set, of every lab release, and of the lab without its gross errors.
NamedFigure lab_gap_figure(const ImpactSet& set, const ImpactSet& lab, const stats::LabGap& gap,
                           double disc_radius_m, const std::string& title);
/// diagnose: held-out error of the base model and of every candidate (+- 1 SE), noise floor and
/// adequacy threshold.
std::vector<NamedFigure> diagnose_figures(const Diagnosis& d, const std::string& title);
/// ladder: in-sample and held-out error per rung falling towards the noise floor, and the
/// held-out error per observable per rung.
std::vector<NamedFigure> ladder_figures(const Ladder& l, const std::string& title);

/// Renders every figure to DIR/STEM.svg; returns the paths written.
std::vector<std::string> render_all(const std::vector<NamedFigure>& figures,
                                    const std::string& dir);

}  // namespace ricochet::diagnosis
