// Figures with gnuplot (SVG or PNG). The only place that writes gnuplot scripts: every command
// that draws builds a Figure and calls render(). The one figure style of the project lives here:
// font, grid, the colour-blind-safe palette (Okabe and Ito 2008, `colour::` below; gnuplot's
// "podo" colour sequence for series without an explicit colour) and the continuous colour map
// (viridis, also colour-blind-safe) of the "circles" style.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace ricochet::report {

/// The Okabe-Ito colours (Okabe and Ito 2008, "Color Universal Design"): distinguishable with
/// every common colour-vision deficiency. Figures name their colours from here only.
namespace colour {
inline constexpr const char* kBlack = "#000000";
inline constexpr const char* kOrange = "#e69f00";
inline constexpr const char* kSkyBlue = "#56b4e9";
inline constexpr const char* kBluishGreen = "#009e73";
inline constexpr const char* kBlue = "#0072b2";
inline constexpr const char* kVermillion = "#d55e00";
inline constexpr const char* kReddishPurple = "#cc79a7";
inline constexpr const char* kGrey = "#888888";
inline constexpr const char* kLightGrey = "#bbbbbb";  ///< solids behind data (a block's outline)
}  // namespace colour

/// One curve or point cloud. Points with a NaN or infinite coordinate (or a non-positive one on
/// a log axis) are not drawn and break lines there; a series without any drawable point keeps
/// its legend entry, marked "(no data)".
struct Series {
  std::string title;  ///< legend text, printed literally (quotes and any character allowed)
  std::vector<double> x, y;
  /// gnuplot style: "lines", "points", "linespoints", "steps" (ECDFs), "errorbars" (uses ylo/yhi),
  /// "filledcurves" (band between ylo and yhi), "circles" (discs of radius `radius`, in x-axis
  /// units, filled by `value` on the panel's colour map; `color` set: one flat colour instead)
  std::string style = "lines";
  std::vector<double> ylo{}, yhi{};  ///< for "errorbars" / "filledcurves"
  std::string color;             ///< gnuplot colour name or "#rrggbb"; empty = automatic
  int point_type = 7;
  std::vector<double> radius{}, value{};  ///< for "circles" (value may be empty when color is set)
};

/// One panel (axes with series).
struct Panel {
  std::string title, xlabel, ylabel;
  std::vector<Series> series;
  bool logx = false, logy = false;
  /// Optional fixed ranges; NaN = automatic.
  double xmin = 0.0 / 0.0, xmax = 0.0 / 0.0, ymin = 0.0 / 0.0, ymax = 0.0 / 0.0;
  /// Legend position. No legend covers data: empty = under the plot (outside bottom center
  /// horizontal); otherwise words among outside (required), left, right, center, top, bottom,
  /// horizontal, vertical, box, nobox; "off" hides the legend.
  std::string key;
  /// One unit of x as long as one unit of y on the page (pictures of space, e.g. a bed section).
  bool equal_aspect = false;
  /// Colour map of "circles" values: label and range (NaN = automatic).
  std::string cblabel;
  double cbmin = 0.0 / 0.0, cbmax = 0.0 / 0.0;
  bool colorbox = true;  ///< draw the colour scale (when a series uses the colour map)
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

/// Renders `figure` with gnuplot (gnuplot-nox) to `path`, whose extension chooses the format:
/// .svg (vector, gnuplot's svg terminal) or .png (raster, gnuplot's libgd png terminal with an
/// indexed palette, at width_px x height_px).
/// Throws std::runtime_error with gnuplot's message when gnuplot is missing or fails. Data go
/// through a temporary file, never through the command line; the file is written only when
/// gnuplot succeeded (parent directories are created). The environment variable
/// RICOCHET_GNUPLOT overrides the gnuplot executable. Throws std::invalid_argument for an
/// inconsistent figure (no panel, x/y lengths differ, unknown style or legend position,
/// malformed colour) or another extension.
void render(const Figure& figure, const std::string& path);

/// Convenience: a panel of ECDFs (one "steps" series per sample, F = i/n as stats::ecdf, non-finite
/// values dropped), y from 0 to 1, legend under the plot.
Panel ecdf_panel(const std::string& title, const std::string& xlabel,
                 const std::vector<std::pair<std::string, std::vector<double>>>& samples);

}  // namespace ricochet::report
