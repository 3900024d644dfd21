// The one CSV writer and the one cell reader: the quoting rule every CSV this project writes
// follows (csv_cell, CsvTable), and its reading side (cells may be double-quoted, unquoted text is
// trimmed; a line starting with '#' is a comment, left to the callers), so that every cell reads
// back unchanged.
#pragma once

#include <cstddef>
#include <functional>
#include <initializer_list>
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

/// The shortest decimal text that reads back to the same double (std::to_chars; "nan", "inf").
std::string shortest_number(double value);

/// A CSV document built in memory and written in one piece: '#' comment lines, then rows of cells
/// (each through csv_cell). Every CSV file the project writes is one of these, so that quoting,
/// number format and the all-or-nothing write are the same everywhere.
class CsvTable {
 public:
  /// One "# ..." line per line of `text`.
  CsvTable& comment(std::string_view text);
  /// One row; the cells are quoted as csv_cell says.
  CsvTable& row(std::span<const std::string> cells);
  CsvTable& row(std::initializer_list<std::string> cells) {
    return row(std::span<const std::string>(cells.begin(), cells.size()));
  }
  /// `v` as a cell: shortest_number(v); NaN and +-inf as an empty cell (the readers' "missing").
  static std::string num(double v);
  /// Writes the document to `path` through write_text_file (nothing half-written is left).
  void write(const std::string& path, const std::string& option = "--out") const;

 private:
  std::string text_;
};

/// Writes `text` to `path` through a temporary file renamed into place (an interrupted or failed
/// write leaves no partial file); throws InputError(path, 0, option, ...) when the file cannot be
/// written.
void write_text_file(const std::string& path, std::string_view text,
                     const std::string& option = "--out");

}  // namespace ricochet
