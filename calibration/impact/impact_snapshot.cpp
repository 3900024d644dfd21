#include "impact/impact_snapshot.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "common/h5.hpp"

namespace ricochet {
namespace {

constexpr const char* kGroup = "/dem/snapshot";

/// Row-major n x w table of w equally long columns; throws std::invalid_argument (naming the
/// frame's step) when their lengths differ.
std::vector<double> table_rows(const std::vector<const std::vector<double>*>& columns, long step) {
  const std::size_t n = columns.front()->size();
  for (const auto* c : columns)
    if (c->size() != n)
      throw std::invalid_argument(
          fmt::format("snapshot: frame of step {} has columns of different lengths", step));
  std::vector<double> rows;
  rows.reserve(n * columns.size());
  for (std::size_t i = 0; i < n; ++i)
    for (const auto* c : columns) rows.push_back((*c)[i]);
  return rows;
}

/// Reads the n x columns.size() table `dset` into the columns; throws std::runtime_error naming
/// the file and the dataset when its shape differs.
void read_table(const h5::File& file, const std::string& dset,
                const std::vector<std::vector<double>*>& columns) {
  std::vector<std::size_t> dims;
  const auto rows = file.read_doubles(dset, &dims);
  const std::size_t w = columns.size();
  if (dims.size() != 2 || dims[1] != w)
    throw std::runtime_error(fmt::format("{}: {} is not an n x {} table", file.path(), dset, w));
  for (std::size_t i = 0; i < dims[0]; ++i)
    for (std::size_t c = 0; c < w; ++c) columns[c]->push_back(rows[w * i + c]);
}

}  // namespace

void write_snapshot(const std::string& path, const ImpactSnapshot& s) {
  // Every table is built (and its columns checked) before the file is touched.
  std::vector<std::pair<std::vector<double>, std::vector<double>>> tables;
  for (const auto& f : s.frames)
    tables.emplace_back(
        table_rows({&f.grain_x_m, &f.grain_z_m, &f.grain_speed_mps, &f.grain_radius_m}, f.step),
        table_rows({&f.block_x_m, &f.block_z_m, &f.block_radius_m}, f.step));
  h5::File file(path, h5::File::Mode::kReadWrite);
  file.remove(kGroup);
  file.create_group(kGroup);
  file.set_attr(kGroup, "impact_id", s.impact_id);
  file.set_attr(kGroup, "section_y_m", s.section_y_m);
  file.set_attr(kGroup, "section_half_width_m", s.section_half_width_m);
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const auto& f = s.frames[k];
    const std::string g = fmt::format("{}/frame_{}", kGroup, k);
    file.create_group(g);
    file.set_attr(g, "step", static_cast<double>(f.step));
    file.set_attr(g, "t_s", f.t_s);
    file.set_attr(g, "max_penetration", f.max_penetration ? 1.0 : 0.0);
    file.write(g + "/grains", tables[k].first, {f.grain_x_m.size(), 4});
    file.write(g + "/block", tables[k].second, {f.block_x_m.size(), 3});
  }
  file.flush();
}

std::optional<ImpactSnapshot> read_snapshot(const std::string& path) {
  if (!h5::is_hdf5(path)) return std::nullopt;
  h5::File file(path, h5::File::Mode::kRead);
  if (!file.exists(kGroup)) return std::nullopt;
  ImpactSnapshot s;
  s.impact_id = file.attr_string(kGroup, "impact_id");
  s.section_y_m = file.attr_double(kGroup, "section_y_m");
  s.section_half_width_m = file.attr_double(kGroup, "section_half_width_m");
  for (std::size_t k = 0;; ++k) {
    const std::string g = fmt::format("{}/frame_{}", kGroup, k);
    if (!file.exists(g)) break;
    SnapshotFrame f;
    f.step = static_cast<long>(file.attr_double(g, "step"));
    f.t_s = file.attr_double(g, "t_s");
    f.max_penetration = file.attr_double(g, "max_penetration") != 0;
    read_table(file, g + "/grains",
               {&f.grain_x_m, &f.grain_z_m, &f.grain_speed_mps, &f.grain_radius_m});
    read_table(file, g + "/block", {&f.block_x_m, &f.block_z_m, &f.block_radius_m});
    s.frames.push_back(std::move(f));
  }
  return s;
}

}  // namespace ricochet
