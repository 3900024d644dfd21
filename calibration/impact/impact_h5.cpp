// The HDF5 form of the impact-set schema (docs/impact-sets.md) and the by-extension dispatch.
//
// Layout: group /impacts with attributes schema = "ricochet-impact-set-1", source, and columns
// (comma-separated column order, so that extras keep their order: HDF5 lists links by name);
// one 1-D dataset per column (strings for id, shape, operator; doubles with a "unit" attribute
// otherwise; NaN or "" = absent optional value); a string dataset "comments" for provenance.
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <unordered_map>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "impact/impact_set.hpp"
#include "impact/schema_detail.hpp"

namespace ricochet {

using namespace impact_detail;

namespace {

constexpr const char* kSchema = "ricochet-impact-set-1";

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

enum class Format { kCsv, kH5 };
Format format_of(const std::string& path) {
  if (ends_with(path, ".csv")) return Format::kCsv;
  if (ends_with(path, ".h5") || ends_with(path, ".hdf5")) return Format::kH5;
  throw InputError(path, 0, "", "unknown file extension; use .csv, .h5 or .hdf5");
}

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const auto comma = s.find(',', start);
    out.push_back(s.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

// One column of the file, read whole.
struct H5Column {
  std::string name;
  const ColumnSpec* spec = nullptr;  // nullptr: extra feature
  std::vector<std::string> text;
  std::vector<double> values;  // SI
  std::size_t extra_index = 0;
};

}  // namespace

namespace {

// The reader proper. `field` names what is being read, for the errors of the HDF5 layer.
void check_schema(const h5::File& file, const std::string& path, const std::string& group,
                  std::string& field) {
  field = "impacts";
  if (!file.exists(group))
    throw InputError(path, 0, "impacts", "no group /impacts: not a Ricochet impact set");
  field = "schema";
  if (!file.has_attr(group, "schema"))
    throw InputError(path, 0, "schema", "group /impacts has no 'schema' attribute");
  const std::string schema = file.attr_string(group, "schema");
  if (schema != kSchema)
    throw InputError(path, 0, "schema",
                     "unsupported schema '" + schema + "' (this version reads " + kSchema + ")");
}

// The column order: the `columns` attribute, else the group's datasets (by name).
std::vector<std::string> column_names(const h5::File& file, const std::string& group,
                                      std::string& field) {
  field = "columns";
  if (file.has_attr(group, "columns")) return split_commas(file.attr_string(group, "columns"));
  std::vector<std::string> names;
  for (const auto& n : file.list(group))
    if (n != "comments") names.push_back(n);
  return names;
}

// The values of a numeric column in SI units, checked against its unit attribute; an extra
// column (no spec) is registered in `set`.
void read_numeric(const h5::File& file, const std::string& path, const std::string& dset,
                  H5Column& col, ImpactSet& set) {
  const std::string& name = col.name;
  std::vector<std::size_t> dims;
  try {
    col.values = file.read_doubles(dset, &dims);
  } catch (const std::runtime_error&) {
    throw InputError(path, 0, name, "numeric column must be a dataset of numbers");
  }
  if (dims.size() != 1) throw InputError(path, 0, name, "dataset must be one-dimensional");
  if (!file.has_attr(dset, "unit"))
    throw InputError(path, 0, name, "numeric dataset has no 'unit' attribute");
  std::string unit;
  try {
    unit = file.attr_string(dset, "unit");
  } catch (const std::runtime_error&) {
    throw InputError(path, 0, name, "attribute 'unit' must be a string");
  }
  const Unit* u = find_unit(unit);
  if (!u)
    throw InputError(path, 0, name,
                     "unknown unit '" + unit + "'; known units: " + units_of(Dim::kText));
  if (col.spec && u->dim != col.spec->dim)
    throw InputError(path, 0, name,
                     "unit '" + unit + "' is not a " + dim_name(col.spec->dim) +
                         " unit; use one of " + units_of(col.spec->dim));
  for (double& v : col.values) v *= u->to_si;
  if (!col.spec) {
    col.extra_index = set.extra_names.size();
    set.extra_names.push_back(name);
    set.extra_units.push_back(si_unit(u->dim));
  }
}

// Every listed column, read whole; all of one length.
std::vector<H5Column> read_columns(const h5::File& file, const std::string& path,
                                   const std::string& group, const std::vector<std::string>& names,
                                   ImpactSet& set,
                                   std::unordered_map<std::string, std::size_t>& seen,
                                   std::size_t& n_rows, std::string& field) {
  std::vector<H5Column> columns;
  bool have_rows = false;
  for (const auto& name : names) {
    H5Column col;
    col.name = name;
    field = name;
    col.spec = find_column(name);
    if (!is_valid_column_name(name) || name == "speed_in")
      throw InputError(path, 0, name, "invalid or reserved column name");
    if (!seen.emplace(name, columns.size()).second)
      throw InputError(path, 0, name, "duplicate column");
    const std::string dset = group + "/" + name;
    if (!file.exists(dset)) throw InputError(path, 0, name, "column listed but no dataset");
    std::size_t size = 0;
    if (col.spec && col.spec->dim == Dim::kText) {
      try {
        col.text = file.read_strings(dset);
      } catch (const std::runtime_error&) {
        throw InputError(path, 0, name, "text column must be a string dataset");
      }
      size = col.text.size();
    } else {
      read_numeric(file, path, dset, col, set);
      size = col.values.size();
    }
    if (have_rows && size != n_rows)
      throw InputError(path, 0, name,
                       "dataset has " + std::to_string(size) + " rows, column '" +
                           columns.front().name + "' has " + std::to_string(n_rows));
    n_rows = size;
    have_rows = true;
    columns.push_back(std::move(col));
  }
  return columns;
}

void check_required(const std::string& path,
                    const std::unordered_map<std::string, std::size_t>& seen) {
  for (const auto& spec : schema_columns())
    if (spec.required && !seen.contains(spec.name))
      throw InputError(path, 0, spec.name,
                       "missing required dataset /impacts/" + std::string(spec.name));
  for (const char* g : {"sigma_vin_", "sigma_vout_"}) {
    const std::string s(g);
    const bool any = seen.contains(s + "x") || seen.contains(s + "y") || seen.contains(s + "w");
    for (const char* c : {"x", "y", "w"})
      if (any && !seen.contains(s + c))
        throw InputError(path, 0, s + c, "missing dataset: " + s + "x, y and w come together");
  }
}

// Row i of every column into one impact; rows are named index + 1 in errors.
void assemble_rows(const std::string& path, const std::vector<H5Column>& columns,
                   std::size_t n_rows, ImpactSet& set) {
  RowAssembler rows(path, "value is NaN", "row");
  for (std::size_t i = 0; i < n_rows; ++i) {
    const std::size_t line = i + 1;
    Impact m;
    m.extra.assign(set.extra_names.size(), std::nan(""));
    for (const H5Column& c : columns) {
      if (c.spec && c.spec->dim == Dim::kText) {
        const std::string& v = c.text[i];
        if (c.spec->col == Col::kId) m.id = v;
        if (c.spec->col == Col::kShape) m.shape = v;
        if (c.spec->col == Col::kOperator && !v.empty()) m.op = v;
        if (c.spec->col == Col::kReplicate && !v.empty()) m.replicate = v;
        continue;
      }
      const double v = c.values[i];
      if (std::isinf(v)) throw InputError(path, line, c.name, "value is infinite");
      if (std::isnan(v)) {
        if (c.spec && c.spec->required) throw InputError(path, line, c.name, "value is NaN");
        continue;  // NaN marks an absent optional value
      }
      rows.store(m, c.spec, c.extra_index, v);
    }
    rows.finish(std::move(m), set, line);
  }
}

ImpactSet read_h5(const h5::File& file, const std::string& path, std::string& field) {
  const std::string group = "/impacts";
  check_schema(file, path, group, field);
  ImpactSet set;
  set.source = path;
  const std::vector<std::string> names = column_names(file, group, field);
  std::unordered_map<std::string, std::size_t> seen;
  std::size_t n_rows = 0;
  const std::vector<H5Column> columns =
      read_columns(file, path, group, names, set, seen, n_rows, field);
  check_required(path, seen);
  field = "";
  assemble_rows(path, columns, n_rows, set);
  if (file.exists(group + "/comments")) {
    try {
      set.comments = file.read_strings(group + "/comments");
    } catch (const std::runtime_error&) {
      throw InputError(path, 0, "comments", "comments must be a string dataset");
    }
  }
  return set;
}

}  // namespace

ImpactSet read_impact_set_h5(const std::string& path) {
  std::unique_ptr<h5::File> file;
  try {
    file = std::make_unique<h5::File>(path, h5::File::Mode::kRead);
  } catch (const std::runtime_error&) {
    throw InputError(path, 0, "", "cannot open as HDF5 (missing file or not an HDF5 file)");
  }
  std::string field;
  try {
    return read_h5(*file, path, field);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    // A damaged file: the HDF5 layer fails on an object the reader found (found by
    // fuzz/fuzz_impact_h5). Name the column or attribute being read.
    throw InputError(path, 0, field, std::string("damaged HDF5 file: ") + e.what());
  }
}

void write_impact_set_h5(const ImpactSet& set, const std::string& path, const std::string& group) {
  validate(set);
  std::string g = group.empty() ? std::string("impacts") : group;
  if (g.front() != '/') g = "/" + g;
  h5::File file(path, h5::File::Mode::kReadWrite);
  file.remove(g);
  file.create_group(g);

  std::string column_list;
  auto add_name = [&](const std::string& n) {
    column_list += (column_list.empty() ? "" : ",") + n;
  };
  const std::size_t n = set.impacts.size();
  for (const auto& spec : schema_columns()) {
    bool used = spec.required;
    for (const auto& m : set.impacts) used = used || has_column(m, spec.col);
    if (!used) continue;
    const std::string dset = g + "/" + spec.name;
    if (spec.dim == Dim::kText) {
      std::vector<std::string> text;
      text.reserve(n);
      for (const auto& m : set.impacts)
        text.push_back(spec.col == Col::kId          ? m.id
                       : spec.col == Col::kShape     ? m.shape
                       : spec.col == Col::kReplicate ? m.replicate.value_or("")
                                                     : m.op.value_or(""));
      file.write_strings(dset, text);
    } else {
      std::vector<double> values;
      values.reserve(n);
      for (const auto& m : set.impacts)
        values.push_back(get_numeric(m, spec.col).value_or(std::nan("")));
      file.write(dset, values);
      file.set_attr(dset, "unit", si_unit(spec.dim));
    }
    add_name(spec.name);
  }
  for (std::size_t k = 0; k < set.extra_names.size(); ++k) {
    std::vector<double> values;
    values.reserve(n);
    for (const auto& m : set.impacts) values.push_back(m.extra[k]);
    const std::string dset = g + "/" + set.extra_names[k];
    file.write(dset, values);
    file.set_attr(dset, "unit", set.extra_units[k]);
    add_name(set.extra_names[k]);
  }
  file.write_strings(g + "/comments", set.comments);
  file.set_attr(g, "schema", kSchema);
  file.set_attr(g, "source", set.source);
  file.set_attr(g, "columns", column_list);
  file.flush();
}

ImpactSet read_impact_set(const std::string& path) {
  return format_of(path) == Format::kCsv ? read_impact_set_csv(path) : read_impact_set_h5(path);
}

ImpactSet read_incident_states(const std::string& path) {
  // HDF5 holds full impact sets only (the design command writes its plans in CSV).
  return format_of(path) == Format::kCsv ? read_incident_states_csv(path)
                                         : read_impact_set_h5(path);
}

void write_impact_set(const ImpactSet& set, const std::string& path) {
  if (format_of(path) == Format::kCsv)
    write_impact_set_csv(set, path);
  else
    write_impact_set_h5(set, path);
}

}  // namespace ricochet
