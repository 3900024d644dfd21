#include "impact/block_track.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/nan.hpp"

namespace ricochet {
namespace {

// The columns in the writer's order: name, SI unit, member.
struct ColumnDef {
  const char* name;
  const char* unit;
  std::vector<double> BlockTrack::*member;
};
const std::vector<ColumnDef>& column_defs() {
  static const std::vector<ColumnDef> defs = {{"t", "s", &BlockTrack::t},
                                              {"x", "m", &BlockTrack::x},
                                              {"y", "m", &BlockTrack::y},
                                              {"theta", "rad", &BlockTrack::theta},
                                              {"vx", "m/s", &BlockTrack::vx},
                                              {"vy", "m/s", &BlockTrack::vy},
                                              {"w", "rad/s", &BlockTrack::w},
                                              {"fcx", "N", &BlockTrack::fcx},
                                              {"fcy", "N", &BlockTrack::fcy},
                                              {"penetration", "m", &BlockTrack::penetration},
                                              {"ke_block", "J", &BlockTrack::ke_block},
                                              {"ke_grains", "J", &BlockTrack::ke_grains},
                                              {"torque", "N*m", &BlockTrack::torque},
                                              {"overlap_d_max", "-", &BlockTrack::overlap_d_max},
                                              {"sigma_fcx", "N", &BlockTrack::sigma_fcx},
                                              {"sigma_fcy", "N", &BlockTrack::sigma_fcy},
                                              {"sigma_torque", "N*m", &BlockTrack::sigma_torque}};
  return defs;
}

std::string trimmed(std::string s) {
  while (!s.empty() && s.back() == ' ') s.pop_back();
  while (!s.empty() && s.front() == ' ') s.erase(0, 1);
  return s;
}

// "torque[N*m]" -> ("torque", "N*m"); "torque" -> ("torque", "").
std::pair<std::string, std::string> split_name(const std::string& cell) {
  const auto b = cell.find('[');
  if (b == std::string::npos) return {trimmed(cell), ""};
  const auto e = cell.find(']', b);
  return {trimmed(cell.substr(0, b)),
          trimmed(cell.substr(b + 1, e == std::string::npos ? e : e - b - 1))};
}

const ColumnDef* find_def(const std::string& name) {
  const std::string bare = split_name(name).first;
  for (const auto& d : column_defs())
    if (bare == d.name) return &d;
  return nullptr;
}

std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> out;
  std::size_t a = 0;
  while (a <= text.size()) {
    const auto b = std::min(text.find(',', a), text.size());
    out.push_back(text.substr(a, b - a));
    a = b + 1;
  }
  return out;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

}  // namespace

const std::vector<std::string>& BlockTrack::column_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& d : column_defs()) n.push_back(fmt::format("{}[{}]", d.name, d.unit));
    return n;
  }();
  return names;
}

std::vector<double>* BlockTrack::column(const std::string& name) {
  const ColumnDef* d = find_def(name);
  return d ? &(this->*(d->member)) : nullptr;
}

const std::vector<double>* BlockTrack::column(const std::string& name) const {
  const ColumnDef* d = find_def(name);
  return d ? &(this->*(d->member)) : nullptr;
}

void BlockTrack::pad() {
  for (const auto& d : column_defs()) (this->*(d.member)).resize(t.size(), kNaN);
}

std::vector<double> BlockTrack::rows() const {
  const auto& defs = column_defs();
  std::vector<double> out;
  out.reserve(size() * defs.size());
  for (std::size_t i = 0; i < size(); ++i)
    for (const auto& d : defs) {
      const auto& c = this->*(d.member);
      out.push_back(i < c.size() ? c[i] : kNaN);
    }
  return out;
}

BlockTrack BlockTrack::from_rows(const std::vector<double>& rows,
                                 const std::vector<std::string>& columns) {
  if (columns.empty() || rows.size() % columns.size() != 0)
    throw std::invalid_argument(
        fmt::format("track: {} values are not a whole number of rows of {} columns", rows.size(),
                    columns.size()));
  BlockTrack tr;
  const std::size_t n = rows.size() / columns.size();
  bool has_t = false;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    auto* col = tr.column(columns[c]);
    if (!col) continue;
    has_t = has_t || col == &tr.t;
    col->resize(n);
    for (std::size_t i = 0; i < n; ++i) (*col)[i] = rows[i * columns.size() + c];
  }
  if (!has_t) throw std::invalid_argument("track: no t column");
  tr.pad();
  return tr;
}

std::vector<std::string> block_track_ids(const std::string& path) {
  if (!h5::is_hdf5(path)) return {};
  const h5::File f(path, h5::File::Mode::kRead);
  if (!f.exists(kTracksGroup)) return {};
  return f.list(kTracksGroup);
}

BlockTrack read_block_track(const std::string& path, const std::string& id) {
  const std::string field = std::string(kTracksGroup) + "/" + id;
  if (!h5::is_hdf5(path)) throw InputError(path, 0, field, "not an HDF5 file: it has no tracks");
  const h5::File f(path, h5::File::Mode::kRead);
  if (!f.exists(field)) throw InputError(path, 0, field, "no such track");
  std::vector<std::string> columns;
  // An attribute of the wrong type is the file's error, located like the others (h5::File
  // throws std::runtime_error for it).
  const auto attribute = [&](const char* name, auto read) {
    try {
      return read();
    } catch (const std::runtime_error& e) {
      throw InputError(path, 0, field, fmt::format("attribute `{}`: {}", name, e.what()));
    }
  };
  if (f.has_attr(field, "columns")) {
    columns = split_commas(attribute("columns", [&] { return f.attr_string(field, "columns"); }));
  } else {
    // Written before the attribute: the first campaigns' twelve columns.
    columns.assign(BlockTrack::column_names().begin(), BlockTrack::column_names().begin() + 12);
  }
  std::vector<std::size_t> dims;
  std::vector<double> rows;
  try {
    rows = f.read_doubles(field, &dims);
  } catch (const std::runtime_error& e) {
    throw InputError(path, 0, field, std::string("not a table of numbers: ") + e.what());
  }
  if (dims.size() != 2 || dims[1] != columns.size())
    throw InputError(path, 0, field,
                     fmt::format("the dataset is {} but its `columns` attribute names {} columns "
                                 "(a track is n records x one column per name)",
                                 dims.size() == 2 ? fmt::format("{} x {}", dims[0], dims[1])
                                                  : fmt::format("of rank {}", dims.size()),
                                 columns.size()));
  for (const auto& c : columns) {
    const auto [name, unit] = split_name(c);
    const ColumnDef* d = find_def(name);
    if (d && !unit.empty() && unit != d->unit)
      throw InputError(path, 0, field,
                       fmt::format("column '{}' is in [{}]; tracks are stored in SI, {}[{}]", name,
                                   unit, d->name, d->unit));
  }
  BlockTrack tr;
  try {
    tr = BlockTrack::from_rows(rows, columns);
  } catch (const std::invalid_argument& e) {
    throw InputError(path, 0, field, fmt::format("{} (columns: {})", e.what(), joined(columns)));
  }
  if (f.has_attr(field, "block_mass_kg")) {
    tr.block_mass_kg =
        attribute("block_mass_kg", [&] { return f.attr_double(field, "block_mass_kg"); });
    // NaN is how a writer says "unknown" (write_block_track then writes no attribute).
    if (!std::isnan(tr.block_mass_kg) && !(std::isfinite(tr.block_mass_kg) && tr.block_mass_kg > 0))
      throw InputError(path, 0, field,
                       fmt::format("attribute `block_mass_kg` is {}: a mass must be finite and > 0 "
                                   "(NaN for unknown)",
                                   tr.block_mass_kg));
  }
  return tr;
}

void write_block_track(const std::string& path, const std::string& id, const BlockTrack& track) {
  if (id.empty()) throw std::invalid_argument("write_block_track: empty id");
  if (track.size() == 0) throw std::invalid_argument("write_block_track: no records in " + id);
  for (const auto& d : column_defs())
    if ((track.*(d.member)).size() > track.size())
      throw std::invalid_argument(
          fmt::format("write_block_track: column {} is longer than t", d.name));
  const std::string field = std::string(kTracksGroup) + "/" + id;
  const auto rows = track.rows();
  h5::File f(path, h5::File::Mode::kReadWrite);
  f.write(field, rows, {track.size(), BlockTrack::column_names().size()});
  f.set_attr(field, "columns", joined(BlockTrack::column_names()));
  f.set_attr(field, "frame", "paper: x flight direction, y up, omega > 0 counter-clockwise");
  if (std::isfinite(track.block_mass_kg)) f.set_attr(field, "block_mass_kg", track.block_mass_kg);
  f.flush();
}

}  // namespace ricochet
