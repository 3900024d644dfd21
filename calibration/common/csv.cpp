#include "common/csv.hpp"

namespace ricochet {
namespace {

// The blanks the reader trims (impact_detail::trim).
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

}  // namespace ricochet
