#include "drop_store.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/csv.hpp"
#include "common/error.hpp"

namespace ricochet::dem {
namespace {

namespace fs = std::filesystem;

std::string num(double v) {
  return std::isfinite(v) ? shortest_number(v) : "nan";
}

std::string kd_cell(const std::optional<KatsuragiDurianFit>& f,
                    double KatsuragiDurianFit::*member) {
  return f ? num((*f).*member) : "nan";
}

}  // namespace

double DropRow::number(const std::string& name) const {
  const auto it = cells.find(name);
  return it == cells.end() ? NAN : std::strtod(it->second.c_str(), nullptr);
}

std::string DropRow::text(const std::string& name) const {
  const auto it = cells.find(name);
  return it == cells.end() ? "" : it->second;
}

const std::vector<std::string>& drop_row_names() {
  static const std::vector<std::string> names = {"id",
                                                 "seed",
                                                 "h_drop_m",
                                                 "status",
                                                 "depth_final_m",
                                                 "depth_max_m",
                                                 "H_total_m",
                                                 "v_impact_mps",
                                                 "v_contact_mps",
                                                 "depth_contact_m",
                                                 "v_rebound_mps",
                                                 "v_free_fall_mps",
                                                 "D_sphere_m",
                                                 "rho_sphere",
                                                 "mass_kg",
                                                 "rho_bulk",
                                                 "t_contact_s",
                                                 "t_penetration_s",
                                                 "kd_samples",
                                                 "kd_g_mps2",
                                                 "kd_g_se",
                                                 "kd_d1_m",
                                                 "kd_d1_se",
                                                 "kd_k_Npm",
                                                 "kd_k_se",
                                                 "kdf_g_mps2",
                                                 "kdf_d1_m",
                                                 "kdf_k_Npm",
                                                 "grains",
                                                 "steps",
                                                 "dt_s",
                                                 "wall_s",
                                                 "cpu_s",
                                                 "sim_time_s",
                                                 "bed_key",
                                                 "message"};
  return names;
}

DropRow drop_row(const DropResult& r, long seed) {
  using F = KatsuragiDurianFit;
  const std::vector<std::string> values = {r.id,
                                           std::to_string(seed),
                                           num(r.h_drop_m),
                                           r.status,
                                           num(r.depth_final_m),
                                           num(r.depth_max_m),
                                           num(r.H_total_m),
                                           num(r.v_impact_mps),
                                           num(r.v_contact_mps),
                                           num(r.depth_contact_m),
                                           num(r.v_rebound_mps),
                                           num(std::sqrt(2 * kDeckGravity_mps2 * r.h_drop_m)),
                                           num(r.D_sphere_m),
                                           num(r.rho_sphere),
                                           num(r.mass_kg),
                                           num(r.rho_bulk),
                                           num(r.t_contact_s),
                                           num(r.t_penetration_s),
                                           std::to_string(r.kd_samples),
                                           kd_cell(r.kd_trajectory, &F::g_mps2),
                                           kd_cell(r.kd_trajectory, &F::g_se),
                                           kd_cell(r.kd_trajectory, &F::d1_m),
                                           kd_cell(r.kd_trajectory, &F::d1_se),
                                           kd_cell(r.kd_trajectory, &F::k_Npm),
                                           kd_cell(r.kd_trajectory, &F::k_se),
                                           kd_cell(r.kd_force, &F::g_mps2),
                                           kd_cell(r.kd_force, &F::d1_m),
                                           kd_cell(r.kd_force, &F::k_Npm),
                                           std::to_string(r.grains),
                                           std::to_string(r.steps),
                                           num(r.dt_s),
                                           num(r.wall_s),
                                           num(r.cpu_s),
                                           num(r.sim_time_s),
                                           r.bed_key,
                                           r.message};
  DropRow row;
  for (std::size_t c = 0; c < values.size(); ++c) row.cells[drop_row_names()[c]] = values[c];
  return row;
}

DropStore::DropStore(std::string csv_path) : path_(std::move(csv_path)) {}

std::string DropStore::tracks_path() const {
  return path_.substr(0, path_.size() - 4) + ".tracks.csv";
}

std::string DropStore::repose_path() const {
  return path_.substr(0, path_.size() - 4) + ".repose.json";
}

std::set<std::string> DropStore::done_ids() const {
  std::set<std::string> done;
  if (fs::exists(path_))
    for (const auto& row : rows()) done.insert(row.text("id"));
  return done;
}

void DropStore::append(const DropResult& r, long seed) const {
  const DropRow row = drop_row(r, seed);
  std::vector<std::string> cells;
  for (const auto& name : drop_row_names()) cells.push_back(row.text(name));
  const bool fresh = !fs::exists(path_);
  {
    std::ofstream f(path_, std::ios::app);
    if (!f) throw InputError(path_, 0, "--out", "cannot write");
    if (fresh) f << csv_row(drop_row_names()) << "\n";
    f << csv_row(cells) << "\n";
  }
  const std::string tp = tracks_path();
  const bool fresh_tracks = !fs::exists(tp);
  std::ofstream f(tp, std::ios::app);
  if (!f) throw InputError(tp, 0, "--out", "cannot write");
  if (fresh_tracks) {
    f << "id";
    for (const auto& c : DropTrack::column_names()) f << "," << c;
    f << "\n";
  }
  for (std::size_t i = 0; i < r.track.size(); ++i) {
    f << r.id;
    for (std::size_t c = 0; c < DropTrack::column_names().size(); ++c)
      f << "," << num(r.track.column(c)[i]);
    f << "\n";
  }
}

std::vector<DropRow> DropStore::rows() const {
  std::vector<DropRow> rows;
  std::ifstream in(path_);
  std::string line;
  std::vector<std::string> header;
  std::size_t lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line[0] == '#') continue;
    auto cells = csv_split(line, path_, lineno, [&](std::size_t i) {
      return i < header.size() ? header[i] : std::string();
    });
    if (header.empty()) {
      header = cells;
      continue;
    }
    if (cells.size() != header.size())
      throw InputError(path_, lineno, "", "expected " + std::to_string(header.size()) + " cells");
    DropRow r;
    for (std::size_t c = 0; c < cells.size(); ++c) r.cells[header[c]] = cells[c];
    rows.push_back(std::move(r));
  }
  return rows;
}

std::map<std::string, DropTrack> DropStore::tracks() const {
  std::map<std::string, DropTrack> tracks;
  const std::string path = tracks_path();
  std::ifstream in(path);
  std::string line;
  bool header = true;
  std::size_t lineno = 0;
  const auto& names = DropTrack::column_names();
  while (std::getline(in, line)) {
    ++lineno;
    if (header) {
      header = false;
      continue;
    }
    const auto cells = csv_split(line, path, lineno, [&](std::size_t i) {
      return i == 0 ? std::string("id") : i - 1 < names.size() ? names[i - 1] : std::string();
    });
    if (cells.size() != names.size() + 1) continue;  // a row cut short by a kill
    auto& tr = tracks[cells[0]];
    for (std::size_t c = 1; c < cells.size(); ++c)
      tr.column(c - 1).push_back(std::strtod(cells[c].c_str(), nullptr));
  }
  return tracks;
}

std::string drop_decks_digest(const Decks& decks) {
  std::uint64_t h = kDemHashSeed;
  for (const char* f :
       {"/drop/setup.in", "/drop/check.in", "/drop/finish.in", "/repose/in.repose"}) {
    std::ifstream in(decks.root + f, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    h = fnv1a(s.str(), h);
  }
  return fmt::format("{:016x}", h);
}

}  // namespace ricochet::dem
