// The one CSV cell writer: the quoting rule every CSV this project writes follows, so that the
// impact-set reader (impact/impact_csv.cpp: cells may be double-quoted, unquoted text is
// trimmed, a line starting with '#' is a comment) reads each cell back unchanged.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace ricochet {

/// `text` as one CSV cell: verbatim, or double-quoted (with " doubled) when it holds a comma or
/// a quote, starts with '#', or has leading or trailing blanks.
std::string csv_cell(std::string_view text);

/// The cells joined by commas (each through csv_cell), without the line end.
std::string csv_row(std::span<const std::string> cells);

}  // namespace ricochet
