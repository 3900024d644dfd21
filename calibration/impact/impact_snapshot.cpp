#include "impact/impact_snapshot.hpp"

#include <fmt/format.h>

#include <fstream>
#include <stdexcept>

#include "common/h5.hpp"

namespace ricochet {
namespace {

constexpr const char* kGroup = "/dem/snapshot";

void check_lengths(const SnapshotFrame& f) {
  const auto n = f.grain_x_m.size(), m = f.block_x_m.size();
  if (f.grain_z_m.size() != n || f.grain_speed_mps.size() != n || f.grain_radius_m.size() != n ||
      f.block_z_m.size() != m || f.block_radius_m.size() != m)
    throw std::invalid_argument(
        fmt::format("snapshot: frame of step {} has columns of different lengths", f.step));
}

bool is_hdf5(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in && std::string(magic, 8) == "\x89HDF\r\n\x1a\n";
}

}  // namespace

void write_snapshot(const std::string& path, const ImpactSnapshot& s) {
  for (const auto& f : s.frames) check_lengths(f);
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
    std::vector<double> grains, block;
    for (std::size_t i = 0; i < f.grain_x_m.size(); ++i)
      grains.insert(grains.end(),
                    {f.grain_x_m[i], f.grain_z_m[i], f.grain_speed_mps[i], f.grain_radius_m[i]});
    for (std::size_t i = 0; i < f.block_x_m.size(); ++i)
      block.insert(block.end(), {f.block_x_m[i], f.block_z_m[i], f.block_radius_m[i]});
    file.write(g + "/grains", grains, {f.grain_x_m.size(), 4});
    file.write(g + "/block", block, {f.block_x_m.size(), 3});
  }
  file.flush();
}

std::optional<ImpactSnapshot> read_snapshot(const std::string& path) {
  if (!is_hdf5(path)) return std::nullopt;
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
    std::vector<std::size_t> dims;
    const auto grains = file.read_doubles(g + "/grains", &dims);
    if (dims.size() != 2 || dims[1] != 4)
      throw std::runtime_error(path + ": " + g + "/grains is not an n x 4 table");
    for (std::size_t i = 0; i < dims[0]; ++i) {
      f.grain_x_m.push_back(grains[4 * i]);
      f.grain_z_m.push_back(grains[4 * i + 1]);
      f.grain_speed_mps.push_back(grains[4 * i + 2]);
      f.grain_radius_m.push_back(grains[4 * i + 3]);
    }
    const auto block = file.read_doubles(g + "/block", &dims);
    if (dims.size() != 2 || dims[1] != 3)
      throw std::runtime_error(path + ": " + g + "/block is not an m x 3 table");
    for (std::size_t i = 0; i < dims[0]; ++i) {
      f.block_x_m.push_back(block[3 * i]);
      f.block_z_m.push_back(block[3 * i + 1]);
      f.block_radius_m.push_back(block[3 * i + 2]);
    }
    s.frames.push_back(std::move(f));
  }
  return s;
}

}  // namespace ricochet
