// The CSV form of the impact-set schema (docs/impact-sets.md): reader and writer.
// Free of HDF5 so that the fuzz target (fuzz/fuzz_impact_csv.cpp) can compile it alone.
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/nan.hpp"
#include "impact/impact_set.hpp"
#include "impact/schema_detail.hpp"

namespace ricochet {

using namespace impact_detail;

namespace {

// One header column as declared in the file.
struct FileColumn {
  std::string name;
  const ColumnSpec* spec = nullptr;  // nullptr: an extra feature
  double to_si = 1.0;
  std::size_t extra_index = 0;
};

// Parses "name[unit]" (unit optional) and classifies the column.
FileColumn parse_header_cell(const std::string& cell, const std::string& file, std::size_t line,
                             std::size_t index, ImpactSet& set) {
  FileColumn col;
  std::string unit;
  bool has_unit = false;
  const auto open = cell.find('[');
  if (open == std::string::npos) {
    col.name = cell;
  } else {
    col.name = std::string(trim(std::string_view(cell).substr(0, open)));
    if (cell.back() != ']' || cell.find('[', open + 1) != std::string::npos ||
        cell.find(']') != cell.size() - 1)
      throw InputError(file, line, col.name.empty() ? cell : col.name,
                       "malformed header cell '" + cell + "'; write name[unit], e.g. vin_x[m/s]");
    unit = std::string(trim(std::string_view(cell).substr(open + 1, cell.size() - open - 2)));
    has_unit = true;
  }
  if (!is_valid_column_name(col.name))
    throw InputError(file, line, col.name.empty() ? "column " + std::to_string(index + 1) : cell,
                     "column names may only use letters, digits and '_' (got '" + cell + "')");

  col.spec = find_column(col.name);
  if (col.spec && col.spec->dim == Dim::kText) {
    if (has_unit)
      throw InputError(file, line, col.name, "text column takes no unit; write just " + col.name);
    return col;
  }
  const Dim want = col.spec ? col.spec->dim : Dim::kText;
  if (!has_unit || unit.empty())
    throw InputError(file, line, col.name,
                     col.spec ? "missing unit; write " + col.name + "[" + si_unit(want) +
                                    "] (accepted: " + units_of(want) + ")"
                              : "unknown column without a unit; an extra feature needs one, e.g. " +
                                    col.name + "[-]");
  const Unit* u = find_unit(unit);
  if (!u)
    throw InputError(file, line, col.name,
                     "unknown unit '" + unit + "'; known units: " + units_of(Dim::kText));
  if (col.spec && u->dim != want)
    throw InputError(
        file, line, col.name,
        "unit '" + unit + "' is not a " + dim_name(want) + " unit; use one of " + units_of(want));
  col.to_si = u->to_si;
  if (!col.spec) {
    if (col.name == "speed_in")
      throw InputError(file, line, col.name, "name is reserved (derived feature |V_in|)");
    col.extra_index = set.extra_names.size();
    set.extra_names.push_back(col.name);
    set.extra_units.push_back(si_unit(u->dim));
  }
  return col;
}

// The header row: the columns, checked for duplicates and for the required ones. Returns
// whether the file gives no reflected column at all (an incident-state file, allowed only when
// `incident_only`).
bool parse_header(std::string_view line, const std::string& name, std::size_t line_no,
                  bool incident_only, ImpactSet& set, std::vector<FileColumn>& columns) {
  const auto cells = csv_split(line, name, line_no,
                               [](std::size_t i) { return "column " + std::to_string(i + 1); });
  std::unordered_map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    columns.push_back(parse_header_cell(cells[i], name, line_no, i, set));
    if (!seen.emplace(columns.back().name, i).second)
      throw InputError(name, line_no, columns.back().name, "duplicate column");
  }
  const bool any_vout = seen.contains("vout_x") || seen.contains("vout_y") || seen.contains("wout");
  const bool no_vout = incident_only && !any_vout;
  for (const auto& spec : schema_columns()) {
    const bool reflected =
        spec.col == Col::kVoutX || spec.col == Col::kVoutY || spec.col == Col::kWout;
    if (spec.required && !seen.contains(spec.name) && !(reflected && no_vout))
      throw InputError(name, line_no, spec.name,
                       incident_only && reflected
                           ? "missing column: vout_x, vout_y and wout come together (or none, "
                             "for incident states)"
                           : "missing required column");
  }
  // The uncertainty of a velocity is all three components or none.
  for (const char* group : {"sigma_vin_", "sigma_vout_"}) {
    const std::string g(group);
    const bool any = seen.contains(g + "x") || seen.contains(g + "y") || seen.contains(g + "w");
    for (const char* c : {"x", "y", "w"})
      if (any && !seen.contains(g + c))
        throw InputError(name, line_no, g + c,
                         "missing column: " + g + "x, " + g + "y and " + g + "w come together");
  }
  return no_vout;
}

// One data row: its cells, in SI units, into one release of `set`.
void parse_row(std::string_view line, const std::string& name, std::size_t line_no,
               const std::vector<FileColumn>& columns, bool no_vout, ImpactSet& set,
               RowAssembler& rows) {
  auto column_name = [&](std::size_t i) {
    return i < columns.size() ? columns[i].name : "column " + std::to_string(i + 1);
  };
  const auto cells = csv_split(line, name, line_no, column_name);
  if (cells.size() != columns.size()) {
    const std::size_t at = std::min(cells.size(), columns.size());
    throw InputError(name, line_no, column_name(at),
                     "row has " + std::to_string(cells.size()) + " cells, the header has " +
                         std::to_string(columns.size()));
  }
  Impact m;
  if (no_vout) m.vout = {kNaN, kNaN, kNaN};
  m.extra.assign(set.extra_names.size(), kNaN);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const FileColumn& c = columns[i];
    const std::string& cell = cells[i];
    if (c.spec && c.spec->dim == Dim::kText) {
      if (c.spec->col == Col::kId) m.id = cell;
      if (c.spec->col == Col::kShape) m.shape = cell;
      if (c.spec->col == Col::kOperator && !cell.empty()) m.op = cell;
      if (c.spec->col == Col::kReplicate && !cell.empty()) m.replicate = cell;
      if (cell.empty() && c.spec->required)
        throw InputError(name, line_no, c.name, "empty cell; every release needs one");
      continue;
    }
    const bool required = c.spec && c.spec->required;
    if (cell.empty()) {
      if (required) throw InputError(name, line_no, c.name, "empty cell");
      continue;  // an optional value that this release does not have
    }
    double v = 0;
    if (!parse_number(cell, v))
      throw InputError(name, line_no, c.name, "not a number (or out of range): '" + cell + "'");
    if (!std::isfinite(v))
      throw InputError(name, line_no, c.name, "value is not finite (NaN or inf): '" + cell + "'");
    rows.store(m, c.spec, c.extra_index, v * c.to_si);
  }
  rows.finish(std::move(m), set, line_no);
}

// The reader of both entry points: `incident_only` (parse_incident_states_csv) lets the three
// reflected columns be absent together; each release's vout is then NaN.
ImpactSet parse_csv(const std::string& text, const std::string& name, bool incident_only) {
  ImpactSet set;
  set.source = name;
  std::vector<FileColumn> columns;
  bool have_header = false;
  bool no_vout = false;  // an incident-state file: no reflected column at all
  RowAssembler rows(name, "empty cell", "line", incident_only);

  std::string_view all(text);
  if (all.starts_with("\xEF\xBB\xBF")) all.remove_prefix(3);  // UTF-8 byte-order mark
  std::size_t pos = 0;
  std::size_t line_no = 0;
  while (pos <= all.size()) {
    const auto nl = all.find('\n', pos);
    std::string_view line = all.substr(pos, nl == std::string_view::npos ? all.npos : nl - pos);
    pos = nl == std::string_view::npos ? all.size() + 1 : nl + 1;
    ++line_no;
    while (!line.empty() && line.back() == '\r') line.remove_suffix(1);  // CRLF files

    if (line.starts_with("#")) {
      line.remove_prefix(1);
      if (line.starts_with(" ")) line.remove_prefix(1);
      set.comments.emplace_back(line);
      continue;
    }
    if (trim(line).empty()) continue;
    if (!have_header) {
      no_vout = parse_header(line, name, line_no, incident_only, set, columns);
      have_header = true;
      continue;
    }
    parse_row(line, name, line_no, columns, no_vout, set, rows);
  }
  if (!have_header)
    throw InputError(
        name, 0, "header",
        "no header row; the first non-comment line must name the columns, e.g. "
        "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s]");
  return set;
}

std::string slurp_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the file for reading");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace

ImpactSet parse_impact_set_csv(const std::string& text, const std::string& name) {
  return parse_csv(text, name, /*incident_only=*/false);
}

ImpactSet parse_incident_states_csv(const std::string& text, const std::string& name) {
  return parse_csv(text, name, /*incident_only=*/true);
}

ImpactSet read_impact_set_csv(const std::string& path) {
  return parse_impact_set_csv(slurp_csv(path), path);
}

ImpactSet read_incident_states_csv(const std::string& path) {
  return parse_incident_states_csv(slurp_csv(path), path);
}

std::string format_impact_set_csv(const ImpactSet& set) {
  validate(set);
  // Optional columns appear only when at least one impact has them; extras always.
  std::vector<const ColumnSpec*> cols;
  for (const auto& spec : schema_columns()) {
    bool used = spec.required;
    for (const auto& m : set.impacts) used = used || has_column(m, spec.col);
    if (used) cols.push_back(&spec);
  }
  std::string out;
  for (const auto& c : set.comments) {
    // A comment is one line; an in-memory comment with line breaks becomes several lines.
    std::string_view rest(c);
    while (true) {
      const auto nl = rest.find('\n');
      out += "# ";
      out += rest.substr(0, nl);
      out += '\n';
      if (nl == std::string_view::npos) break;
      rest.remove_prefix(nl + 1);
    }
  }
  std::string header;
  for (const ColumnSpec* c : cols) {
    if (!header.empty()) header += ',';
    header += c->name;
    if (c->dim != Dim::kText) header += std::string("[") + si_unit(c->dim) + "]";
  }
  for (std::size_t k = 0; k < set.extra_names.size(); ++k)
    header += "," + set.extra_names[k] + "[" + set.extra_units[k] + "]";
  out += header + '\n';
  for (const auto& m : set.impacts) {
    std::string row;
    for (const ColumnSpec* c : cols) {
      if (!row.empty()) row += ',';
      switch (c->col) {
        case Col::kId:
          row += csv_cell(m.id);
          break;
        case Col::kShape:
          row += csv_cell(m.shape);
          break;
        case Col::kOperator:
          if (m.op) row += csv_cell(*m.op);
          break;
        case Col::kReplicate:
          if (m.replicate) row += csv_cell(*m.replicate);
          break;
        default:
          if (const auto v = get_numeric(m, c->col)) row += shortest_number(*v);
      }
    }
    for (double v : m.extra) {
      row += ',';
      if (!std::isnan(v)) row += shortest_number(v);
    }
    out += row + '\n';
  }
  return out;
}

void write_impact_set_csv(const ImpactSet& set, const std::string& path) {
  write_text_file(path, format_impact_set_csv(set), "--out");
}

}  // namespace ricochet
