#include "bed.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "common/clock.hpp"
#include "liggghts.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;

BedFiles read_bed_files(const std::string& prefix) {
  const std::string path = prefix + ".params";
  std::ifstream in(path);
  if (!in) throw std::runtime_error("bed: cannot read " + path);
  BedFiles b;
  b.prefix = prefix;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string kw, name, style, value;
    if (ls >> kw >> name >> style >> value && kw == "variable" && style == "string")
      b.values[name] = value;
  }
  auto num = [&](const char* name) {
    const auto it = b.values.find(name);
    if (it == b.values.end())
      throw std::runtime_error("bed: " + path + " has no value for " + name +
                               " (written by an older in.bed? delete it to rebuild)");
    return std::strtod(it->second.c_str(), nullptr);
  };
  b.mode = b.values.count("mode") ? b.values.at("mode") : "";
  b.grains = static_cast<long>(num("bed_grains"));
  b.Lx_m = num("Lx_m");
  b.Ly_m = num("Ly_m");
  b.H_m = num("H_m");
  b.z_surface_m = num("z_surface_m");
  b.z_box_top_m = num("z_box_top_m");
  b.r_max_m = std::max({num("r1_m"), num("r2_m"), num("r3_m")});
  b.dt_s = num("bed_dt_s");
  b.settle_time_s = num("bed_time_s");
  b.settled = num("bed_settled") == 1.0;
  return b;
}

std::string bed_prefix(const std::string& cache_dir, const std::string& key) {
  return (fs::path(cache_dir) / ("bed-" + key)).string();
}

bool bed_cached(const std::string& cache_dir, const std::string& key) {
  const std::string prefix = bed_prefix(cache_dir, key);
  return fs::exists(prefix + ".restart") && fs::exists(prefix + ".params");
}

bool bed_building(const std::string& cache_dir, const std::string& key) {
  const int fd = ::open((bed_prefix(cache_dir, key) + ".lock").c_str(), O_RDONLY);
  if (fd < 0) return false;  // never built here
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0;
  ::close(fd);  // releases the shared lock if it was taken
  return held;
}

namespace {

// The files of the build PREFIX.building: PREFIX.building.ckpt-* (checkpoints, complete or not).
std::vector<fs::path> bed_checkpoint_files(const std::string& building_prefix) {
  const fs::path base(building_prefix);
  const fs::path dir = base.has_parent_path() ? base.parent_path() : fs::path(".");
  const std::string head = base.filename().string() + ".ckpt-";
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().filename().string().starts_with(head)) files.push_back(e.path());
  return files;
}

}  // namespace

std::optional<BedCheckpoint> latest_bed_checkpoint(const std::string& building_prefix) {
  const std::string head = fs::path(building_prefix).filename().string() + ".ckpt-";
  std::optional<BedCheckpoint> best;
  for (const auto& path : bed_checkpoint_files(building_prefix)) {
    const std::string name = path.filename().string();
    if (!name.ends_with(".restart")) continue;
    BedCheckpoint c;
    char tail = 0;
    const std::string state = name.substr(head.size(), name.size() - head.size() - 8);
    if (std::sscanf(state.c_str(), "%d-%ld-%d%c", &c.phase, &c.chunk, &c.settled_pour, &tail) !=
            3 ||
        c.phase < 1 || c.phase > 3 || c.chunk < 1)
      continue;  // ckpt-new (being written) and anything else
    c.path = path.string();
    if (!best || std::pair(c.phase, c.chunk) > std::pair(best->phase, best->chunk)) best = c;
  }
  return best;
}

BedFiles ensure_bed(const Decks& decks, const std::map<std::string, std::string>& bed_overrides,
                    const std::string& cache_dir, MPI_Comm comm, bool* built, double* wall_s,
                    long checkpoint_steps) {
  const std::string key = bed_key(decks, bed_overrides);
  const std::string prefix = bed_prefix(cache_dir, key);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  // Another process (a parallel test, a second campaign) may be building the same bed: rank 0
  // holds an flock on PREFIX.lock from the existence check to the end of the build.
  int lock_fd = -1;
  if (rank == 0) {
    fs::create_directories(cache_dir);
    lock_fd = ::open((prefix + ".lock").c_str(), O_RDWR | O_CREAT, 0644);
    if (lock_fd >= 0) ::flock(lock_fd, LOCK_EX);
  }
  int have = 0;
  if (rank == 0) have = bed_cached(cache_dir, key);
  // A previous build that LIGGGHTS stopped with an error (it ends the process) left its message in
  // the screen file: building again would stop this process too, so report it instead.
  std::string failed;
  if (rank == 0 && !have) {
    std::ifstream screen(prefix + ".screen");
    std::string line;
    while (std::getline(screen, line))
      if (line.rfind("ERROR", 0) == 0) failed = line;
  }
  int n_failed = static_cast<int>(failed.size());
  MPI_Bcast(&n_failed, 1, MPI_INT, 0, comm);
  failed.resize(static_cast<std::size_t>(n_failed));
  MPI_Bcast(failed.data(), n_failed, MPI_CHAR, 0, comm);
  if (!failed.empty()) {
    if (lock_fd >= 0) ::close(lock_fd);
    throw std::runtime_error("the bed " + prefix + " failed to build in an earlier run: " + failed +
                             " (fix the parameters, or delete " + prefix + ".screen to try again)");
  }
  MPI_Bcast(&have, 1, MPI_INT, 0, comm);
  if (built) *built = !have;
  if (wall_s) *wall_s = 0;
  if (!have) {
    // Build under a temporary name and rename when complete: a killed build leaves no bed that
    // looks finished, and a concurrent reader never sees half a restart file.
    const std::string tmp = prefix + ".building";
    // A build that a kill interrupted goes on from its latest checkpoint (rank 0 reads the
    // folder; the state is in the file's name).
    BedCheckpoint resume;
    if (rank == 0) {
      if (const auto c = latest_bed_checkpoint(tmp)) resume = *c;
    }
    long state[3] = {resume.phase, resume.chunk, resume.settled_pour};
    MPI_Bcast(state, 3, MPI_LONG, 0, comm);
    int n_path = static_cast<int>(resume.path.size());
    MPI_Bcast(&n_path, 1, MPI_INT, 0, comm);
    resume.path.resize(static_cast<std::size_t>(n_path));
    MPI_Bcast(resume.path.data(), n_path, MPI_CHAR, 0, comm);
    const auto check_every = static_cast<long>(bed_param(decks, bed_overrides, "check_every"));
    const long ckpt_every = checkpoint_steps > 0 && check_every > 0
                                ? (checkpoint_steps + check_every - 1) / check_every
                                : 0;
    if (rank == 0 && state[0] > 0)
      std::cerr << "[dem] bed " << key << ": resuming its build from its checkpoint (phase "
                << state[0] << ", chunk " << state[1] << ")\n";
    const auto start = std::chrono::steady_clock::now();
    {
      std::vector<std::pair<std::string, std::string>> vars = {
          {"common", decks.common}, {"bed", tmp}, {"ckpt_every", std::to_string(ckpt_every)}};
      if (state[0] > 0) {
        vars.emplace_back("resume_phase", std::to_string(state[0]));
        vars.emplace_back("resume_chunk", std::to_string(state[1]));
        vars.emplace_back("resume_settled_pour", std::to_string(state[2]));
        vars.emplace_back("restart_in", resume.path);
      }
      for (const auto& [name, value] : bed_overrides) vars.emplace_back(name, value);
      Liggghts lmp(comm, prefix + ".log", prefix + ".screen", vars);
      lmp.file(decks.bed_deck);
    }
    if (wall_s) *wall_s = seconds_since(start);
    if (rank == 0) {
      // The parameters file goes last: its presence marks a complete bed.
      fs::rename(tmp + ".restart", prefix + ".restart");
      fs::rename(tmp + ".params", prefix + ".params");
      std::error_code ec;  // a checkpoint left behind only costs disk
      for (const auto& f : bed_checkpoint_files(tmp)) fs::remove(f, ec);
    }
    MPI_Barrier(comm);
  }
  if (lock_fd >= 0) {
    ::flock(lock_fd, LOCK_UN);
    ::close(lock_fd);
  }
  BedFiles b = read_bed_files(prefix);
  b.key = key;
  return b;
}

BedPacking measure_packing(const BedFiles& bed, MPI_Comm comm) {
  const std::string restart = bed.prefix + ".restart";
  if (!fs::exists(restart)) throw std::runtime_error("bed: no restart file " + restart);
  const auto rho = bed.values.find("rho_grain");
  if (rho == bed.values.end())
    throw std::runtime_error("bed: " + bed.prefix + ".params has no value for rho_grain");
  Liggghts lmp(comm, bed.prefix + ".packing.log", bed.prefix + ".packing.screen", {});
  lmp.read_bed_restart(restart);
  const Liggghts::LocalAtoms atoms = lmp.local_atoms();
  double local[2] = {0, 0};  // grains, volume
  for (std::size_t i = 0; i < atoms.radius.size(); ++i) {
    if (atoms.type[i] != 1) continue;  // in.bed's grains are type 1
    local[0] += 1;
    local[1] += 4.0 / 3.0 * M_PI * std::pow(atoms.radius[i], 3);
  }
  double total[2] = {0, 0};
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, comm);
  if (total[0] < 1) throw std::runtime_error("bed: " + restart + " holds no grain (type 1)");
  BedPacking p;
  p.grains = static_cast<long>(total[0]);
  p.grain_volume_m3 = total[1];
  p.bed_volume_m3 = bed.Lx_m * bed.Ly_m * bed.z_surface_m;
  p.solid_fraction = p.grain_volume_m3 / p.bed_volume_m3;
  p.bulk_density_kg_m3 = p.solid_fraction * std::strtod(rho->second.c_str(), nullptr);
  return p;
}

GrainCountPacking grain_count_packing(const std::vector<BedPacking>& references) {
  if (references.empty())
    throw std::invalid_argument("grain_count_packing: no reference bed of the same geometry");
  std::vector<double> f;
  for (const auto& r : references) {
    if (r.grains <= 0 || !(r.grain_volume_m3 > 0) || !(r.bed_volume_m3 > 0))
      throw std::invalid_argument("grain_count_packing: a reference bed without grains or volume");
    f.push_back(r.grain_volume_m3 / static_cast<double>(r.grains) / r.bed_volume_m3);
  }
  GrainCountPacking g;
  g.references = f.size();
  double sum = 0;
  for (double v : f) sum += v;
  g.per_grain = sum / static_cast<double>(f.size());
  if (f.size() >= 2) {
    g.loo_max_abs = 0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      const double others = (sum - f[i]) / static_cast<double>(f.size() - 1);
      g.loo_max_abs =
          std::max(g.loo_max_abs, std::fabs(references[i].solid_fraction -
                                            static_cast<double>(references[i].grains) * others));
    }
  }
  return g;
}

}  // namespace ricochet::dem
