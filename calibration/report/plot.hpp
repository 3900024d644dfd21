// Figures with gnuplot (SVG). The only place that writes gnuplot scripts: every command that
// draws builds a Figure and calls render().
#pragma once

#include <string>
#include <vector>

namespace ricochet::report {

/// One curve or point cloud.
struct Series {
  std::string title;
  std::vector<double> x, y;
  /// gnuplot style: "lines", "points", "linespoints", "steps" (ECDFs), "errorbars" (uses ylo/yhi)
  std::string style = "lines";
  std::vector<double> ylo, yhi;  ///< for "errorbars" / "filledcurves"
  std::string color;             ///< gnuplot colour name or "#rrggbb"; empty = automatic
  int point_type = 7;
};

/// One panel (axes with series).
struct Panel {
  std::string title, xlabel, ylabel;
  std::vector<Series> series;
  bool logx = false, logy = false;
  /// Optional fixed ranges; NaN = automatic.
  double xmin = 0.0 / 0.0, xmax = 0.0 / 0.0, ymin = 0.0 / 0.0, ymax = 0.0 / 0.0;
};

/// A figure: panels laid out in a grid of `columns` columns.
struct Figure {
  std::string title;
  std::vector<Panel> panels;
  int columns = 3;
  int width_px = 1200, height_px = 400;
};

/// Renders `figure` to an SVG file with gnuplot (gnuplot-nox). Throws std::runtime_error with
/// gnuplot's message when gnuplot is missing or fails. Data go through a temporary file, never
/// through the command line.
void render_svg(const Figure& figure, const std::string& svg_path);

/// Convenience: a panel of ECDFs (one "steps" series per sample).
Panel ecdf_panel(const std::string& title, const std::string& xlabel,
                 const std::vector<std::pair<std::string, std::vector<double>>>& samples);

}  // namespace ricochet::report
