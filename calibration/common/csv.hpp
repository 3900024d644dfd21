// The one CSV cell writer and the one cell reader: the quoting rule every CSV this project writes
// follows, and its reading side (cells may be double-quoted, unquoted text is trimmed; a line
// starting with '#' is a comment, left to the callers), so that every cell reads back unchanged.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ricochet {

/// `text` as one CSV cell: verbatim, or double-quoted (with " doubled) when it holds a comma or
/// a quote, starts with '#', or has leading or trailing blanks.
std::string csv_cell(std::string_view text);

/// The cells joined by commas (each through csv_cell), without the line end.
std::string csv_row(std::span<const std::string> cells);

/// `text` without the blanks the reader trims around an unquoted cell (space, tab, CR, VT, FF).
std::string_view csv_trim(std::string_view text);

/// Splits one line into cells. Cells may be double-quoted ("a,b", "say ""hi"""); quoted text is
/// kept verbatim, unquoted text is trimmed. A quoted cell cannot span lines. Throws
/// InputError(file, line_no, column_name(i), ...) on an unterminated quote or text after a
/// closing quote in cell i.
std::vector<std::string> csv_split(std::string_view line, const std::string& file,
                                   std::size_t line_no,
                                   const std::function<std::string(std::size_t)>& column_name);

}  // namespace ricochet
