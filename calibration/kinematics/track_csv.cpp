// The track CSV reader (docs/impact-sets.md, "Tracks"; docs/commands/reconstruct.md): a
// tracked video's or a simulation's centre and angle over time, with units in the header,
// pixels scaled by the pixel size. Its declarations are in reconstruct.hpp, beside the
// reconstruction that reads its Track.
#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/nan.hpp"
#include "common/units.hpp"
#include "kinematics/reconstruct.hpp"
#include "stats/median.hpp"

namespace ricochet::kinematics {
namespace {

using units::Dim;

// The track's own unit besides the shared table: image pixels, scaled by --pixel-size.
constexpr std::string_view kPixels = "px";

/// Factor to SI of a unit of the given dimension (the shared table, common/units.hpp); nullopt
/// if the unit does not fit. For lengths, `px` returns 0 (scaled later by the pixel size).
std::optional<double> unit_factor(Dim dim, const std::string& unit) {
  if (dim == Dim::kLength && unit == kPixels) return 0.0;
  if (const units::Unit* u = units::find_unit(unit, dim)) return u->to_si;
  return std::nullopt;
}

/// The units a track column accepts, for messages: "px, m, cm, mm" for lengths.
std::string track_units_of(Dim dim) {
  return (dim == Dim::kLength ? std::string(kPixels) + ", " : std::string()) + units::units_of(dim);
}

struct TrackColumn {
  const char* name;
  Dim quantity;
  int index = -1;     // position in the row, -1 if absent
  double factor = 1;  // to SI
  bool pixels = false;
};

double parse_cell(const std::string& cell, const std::string& file, std::size_t line,
                  const std::string& column) {
  double v = 0;
  const char* first = cell.data();
  const char* last = cell.data() + cell.size();
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (cell.empty() || ec != std::errc() || ptr != last)
    throw InputError(file, line, column, "'" + cell + "' is not a number");
  if (!std::isfinite(v))
    throw InputError(file, line, column, "value must be finite, got '" + cell + "'");
  return v;
}

/// Adds multiples of 2 pi so that consecutive angles differ by less than pi (the camera frame
/// rate must resolve the rotation: less than half a turn between frames).
void unwrap(std::vector<double>& theta) {
  double offset = 0;
  for (std::size_t i = 1; i < theta.size(); ++i) {
    const double raw = theta[i] + offset;
    const double d = raw - theta[i - 1];
    offset -= 2 * std::numbers::pi * std::round(d / (2 * std::numbers::pi));
    theta[i] += offset;
  }
}

}  // namespace

Track parse_track_csv(const std::string& text, const std::string& name,
                      std::optional<double> pixel_size_m, bool image_y_down) {
  if (pixel_size_m && !(std::isfinite(*pixel_size_m) && *pixel_size_m > 0))
    throw InputError(name, 0, "--pixel-size", "pixel size must be a positive number of m/px");
  std::istringstream in(text);
  std::string line;
  std::size_t lineno = 0, header_line = 0;
  std::vector<TrackColumn> cols = {{"t", Dim::kTime},        {"x", Dim::kLength},
                                   {"y", Dim::kLength},      {"mark_x", Dim::kLength},
                                   {"mark_y", Dim::kLength}, {"theta", Dim::kAngle}};
  enum { kT, kX, kY, kMx, kMy, kTheta };
  std::size_t width = 0;
  std::vector<std::string> header_names;
  std::vector<std::array<double, 6>> rows;
  std::vector<std::size_t> row_lines;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string_view trimmed = csv_trim(line);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    // The CSV cell rule of every reader (common/csv.hpp); an error names the column.
    const std::vector<std::string> cells =
        csv_split(trimmed, name, lineno, [&](std::size_t c) -> std::string {
          return c < header_names.size() ? header_names[c] : "column " + std::to_string(c + 1);
        });
    if (header_line == 0) {
      header_line = lineno;
      width = cells.size();
      for (const std::string& cell : cells)
        header_names.emplace_back(csv_trim(std::string_view(cell).substr(0, cell.find('['))));
      for (std::size_t c = 0; c < cells.size(); ++c) {
        const std::string& cell = cells[c];
        const auto open = cell.find('[');
        const std::string cname(csv_trim(std::string_view(cell).substr(0, open)));
        for (TrackColumn& col : cols) {
          if (cname != col.name) continue;
          if (col.index >= 0) throw InputError(name, lineno, cname, "column appears twice");
          if (open == std::string::npos || cell.back() != ']')
            throw InputError(name, lineno, cname,
                             std::string("missing unit: write ") + col.name +
                                 "[unit] with unit in " + track_units_of(col.quantity));
          const std::string unit(
              csv_trim(std::string_view(cell).substr(open + 1, cell.size() - open - 2)));
          const auto f = unit_factor(col.quantity, unit);
          if (!f)
            throw InputError(
                name, lineno, cname,
                "unknown unit '" + unit + "' (use " + track_units_of(col.quantity) + ")");
          col.index = static_cast<int>(c);
          col.pixels = col.quantity == Dim::kLength && *f == 0;
          col.factor = *f;
        }
      }
      for (int required : {kT, kX, kY})
        if (cols[required].index < 0)
          throw InputError(name, lineno, cols[required].name, "missing column");
      const bool marks = cols[kMx].index >= 0 || cols[kMy].index >= 0;
      if (marks && cols[kMx].index < 0) throw InputError(name, lineno, "mark_x", "missing column");
      if (marks && cols[kMy].index < 0) throw InputError(name, lineno, "mark_y", "missing column");
      if (marks && cols[kTheta].index >= 0)
        throw InputError(name, lineno, "theta", "give either mark_x, mark_y or theta, not both");
      if (!marks && cols[kTheta].index < 0)
        throw InputError(name, lineno, "mark_x",
                         "missing column: the rotation needs mark_x and mark_y (eccentric mark) "
                         "or theta");
      bool any_px = false;
      for (TrackColumn& col : cols) {
        if (col.index < 0 || col.quantity != Dim::kLength) continue;
        if (col.pixels) {
          any_px = true;
          if (!pixel_size_m)
            throw InputError(name, lineno, col.name,
                             "coordinates in px need the pixel size (--pixel-size M, in m/px)");
          col.factor = *pixel_size_m;
        }
      }
      if (!any_px && pixel_size_m)
        throw InputError(name, lineno, "x",
                         "--pixel-size applies to px columns, but this track is in mm or m");
      continue;
    }
    if (cells.size() != width)
      throw InputError(
          name, lineno, cells.size() < width ? header_names[cells.size()] : "(extra cell)",
          "expected " + std::to_string(width) + " cells, found " + std::to_string(cells.size()));
    std::array<double, 6> row{};
    for (std::size_t k = 0; k < cols.size(); ++k) {
      if (cols[k].index < 0) continue;
      row[k] =
          parse_cell(cells[static_cast<std::size_t>(cols[k].index)], name, lineno, cols[k].name) *
          cols[k].factor;
    }
    if (!rows.empty() && !(row[kT] > rows.back()[kT]))
      throw InputError(name, lineno, "t", "time must increase strictly from row to row");
    rows.push_back(row);
    row_lines.push_back(lineno);
  }
  if (header_line == 0) throw InputError(name, 0, "", "no header row (expected t[s],x[px],...)");
  if (rows.size() < 6)
    throw InputError(name, lineno, "",
                     "a track needs at least 6 rows, found " + std::to_string(rows.size()));
  Track tr;
  tr.source = name;
  const double ysign = image_y_down ? -1 : 1;
  const bool marks = cols[kMx].index >= 0;
  std::vector<double> radius;
  for (const auto& r : rows) {
    tr.t.push_back(r[kT]);
    tr.x.push_back(r[kX]);
    tr.y.push_back(ysign * r[kY]);
    if (marks) {
      const double dx = r[kMx] - r[kX], dy = ysign * r[kMy] - ysign * r[kY];
      tr.theta.push_back(std::atan2(dy, dx));
      radius.push_back(std::hypot(dx, dy));
    } else {
      tr.theta.push_back(r[kTheta]);
    }
  }
  if (marks) {
    for (std::size_t i = 0; i < radius.size(); ++i)
      if (radius[i] == 0)
        throw InputError(name, row_lines[i], "mark_x",
                         "the eccentric mark coincides with the centre: no rotation angle");
    tr.mark_radius_m = stats::median(radius);
  }
  unwrap(tr.theta);
  if (cols[kX].pixels) tr.resolution_m = *pixel_size_m;
  return tr;
}

Track read_track_csv(const std::string& path, std::optional<double> pixel_size_m,
                     bool image_y_down) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the track file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_track_csv(text.str(), path, pixel_size_m, image_y_down);
}

}  // namespace ricochet::kinematics
