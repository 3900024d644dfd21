#include "common/csv.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/error.hpp"

namespace ricochet {
namespace {

// The blanks the reader trims (csv_trim).
bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

bool needs_quotes(std::string_view s) {
  if (s.empty()) return false;
  if (s.find_first_of(",\"") != std::string_view::npos) return true;
  if (s.front() == '#') return true;
  return is_blank(s.front()) || is_blank(s.back());
}

}  // namespace

std::string_view csv_trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

std::string csv_cell(std::string_view text) {
  if (!needs_quotes(text)) return std::string(text);
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + '"';
}

std::string csv_row(std::span<const std::string> cells) {
  std::string row;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) row += ',';
    row += csv_cell(cells[i]);
  }
  return row;
}

std::vector<std::string> csv_split(std::string_view line, const std::string& file,
                                   std::size_t line_no,
                                   const std::function<std::string(std::size_t)>& column_name) {
  std::vector<std::string> cells;
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::string cell;
    if (i < line.size() && line[i] == '"') {
      ++i;
      bool closed = false;
      while (i < line.size()) {
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            cell += '"';
            i += 2;
            continue;
          }
          ++i;
          closed = true;
          break;
        }
        cell += line[i++];
      }
      if (!closed) throw InputError(file, line_no, column_name(cells.size()), "unterminated quote");
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      if (i < line.size() && line[i] != ',')
        throw InputError(file, line_no, column_name(cells.size()),
                         "unexpected text after a closing quote");
    } else {
      const auto comma = line.find(',', i);
      const auto end = comma == std::string_view::npos ? line.size() : comma;
      cell = std::string(csv_trim(line.substr(i, end - i)));
      i = end;
    }
    cells.push_back(std::move(cell));
    if (i >= line.size()) break;
    ++i;  // the comma
  }
  return cells;
}

CsvTable& CsvTable::comment(std::string_view text) {
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find('\n', start);
    text_ += "# ";
    text_ += text.substr(start, end == std::string_view::npos ? end : end - start);
    text_ += '\n';
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return *this;
}

CsvTable& CsvTable::row(std::span<const std::string> cells) {
  text_ += csv_row(cells);
  text_ += '\n';
  return *this;
}

std::string shortest_number(double value) {
  std::array<char, 64> buf;
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), value);
  return std::string(buf.data(), res.ptr);
}

std::string CsvTable::num(double v) {
  return std::isfinite(v) ? shortest_number(v) : std::string();
}

void CsvTable::write(const std::string& path, const std::string& option) const {
  write_text_file(path, text_, option);
}

void write_text_file(const std::string& path, std::string_view text, const std::string& option) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw InputError(path, 0, option, "cannot open the file for writing");
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!f.flush()) {
      f.close();
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw InputError(path, 0, option, "write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(path, 0, option, "cannot move the written file into place");
  }
}

}  // namespace ricochet
