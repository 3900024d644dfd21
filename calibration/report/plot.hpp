// Figures with gnuplot (SVG). The only place that writes gnuplot scripts: every command that
// draws builds a Figure and calls render().
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace ricochet::report {

/// One curve or point cloud. Points with a NaN or infinite coordinate (or a non-positive one on
/// a log axis) are not drawn and break lines there; a series without any drawable point keeps
/// its legend entry, marked "(no data)".
struct Series {
  std::string title;  ///< legend text, printed literally (quotes and any character allowed)
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
  /// Legend position: empty = gnuplot default (top right), else words among left, right,
  /// center, top, bottom, inside, outside, horizontal, box, nobox, opaque; "off" hides the
  /// legend.
  std::string key;
};

/// A figure: panels laid out in a grid of `columns` columns.
struct Figure {
  std::string title;
  std::vector<Panel> panels;
  int columns = 3;
  int width_px = 1200, height_px = 400;  ///< size of the whole figure
  /// false: titles and labels are printed literally (an underscore stays an underscore);
  /// true: gnuplot enhanced text (V_{in}^x gives sub- and superscripts).
  bool enhanced_text = false;
};

/// Renders `figure` to an SVG file with gnuplot (gnuplot-nox). Throws std::runtime_error with
/// gnuplot's message when gnuplot is missing or fails. Data go through a temporary file, never
/// through the command line; the SVG is written only when gnuplot succeeded (parent directories
/// are created). The environment variable RICOCHET_GNUPLOT overrides the gnuplot executable.
/// Throws std::invalid_argument for an inconsistent figure (no panel, x/y lengths differ,
/// unknown style or legend position, malformed colour).
void render_svg(const Figure& figure, const std::string& svg_path);

/// Convenience: a panel of ECDFs (one "steps" series per sample, F = i/n as stats::ecdf, non-finite
/// values dropped), y from 0 to 1, legend bottom right.
Panel ecdf_panel(const std::string& title, const std::string& xlabel,
                 const std::vector<std::pair<std::string, std::vector<double>>>& samples);

}  // namespace ricochet::report
