#include "liggghts.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <stdexcept>

// LIGGGHTS headers (libliggghts-dev): the C interface plus the Variable class, whose retrieve()
// returns any variable's value as text (the C interface cannot tell a variable's style).
#include <input.h>
#include <lammps.h>
#include <library.h>
#include <variable.h>
// ... and, for the overlap probe, the atoms, the pair style's neighbour list and fix external.
#include <atom.h>
#include <fix_external.h>
#include <force.h>
#include <modify.h>
#include <neigh_list.h>
#include <pair.h>
#include <update.h>

namespace ricochet::dem {

namespace {

// LIGGGHTS writes a few lines to stdout whatever -screen says (e.g. read_restart prints the
// restart's version). stdout belongs to the caller (--json promises one JSON document there):
// point it at /dev/null while LIGGGHTS runs. Opening a second instance in one process also prints
// hundreds of harmless "Style collision detected" lines (its style tables are static and filled
// again) on stderr: the constructor silences stderr too (its errors go to the screen file).
class Quiet {
 public:
  explicit Quiet(bool also_stderr = false) {
    std::fflush(stdout);
    std::fflush(stderr);
    const int null = ::open("/dev/null", O_WRONLY);
    for (int fd : {1, 2}) {
      if (fd == 2 && !also_stderr) continue;
      saved_[fd - 1] = ::dup(fd);
      if (saved_[fd - 1] >= 0 && null >= 0) ::dup2(null, fd);
    }
    if (null >= 0) ::close(null);
  }
  ~Quiet() {
    std::fflush(stdout);
    std::fflush(stderr);
    for (int fd : {1, 2})
      if (saved_[fd - 1] >= 0) {
        ::dup2(saved_[fd - 1], fd);
        ::close(saved_[fd - 1]);
      }
  }
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;

 private:
  int saved_[2] = {-1, -1};
};

}  // namespace

Liggghts::Liggghts(MPI_Comm comm, const std::string& log_path, const std::string& screen_path,
                   const std::vector<std::pair<std::string, std::string>>& variables)
    : comm_(comm) {
  std::vector<std::string> args = {"liggghts", "-log", log_path, "-screen", screen_path};
  for (const auto& [name, value] : variables) {
    args.push_back("-var");
    args.push_back(name);
    args.push_back(value);
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  Quiet quiet(/*also_stderr=*/true);
  lammps_open(static_cast<int>(args.size()), argv.data(), comm, &lmp_);
  if (!lmp_) throw std::runtime_error("LIGGGHTS: lammps_open failed");
}

struct Liggghts::OverlapProbeState {
  LAMMPS_NS::LAMMPS* lmp = nullptr;
  int body_type = 0;
  /// step -> largest delta / d on this rank (a step sampled twice, by a run's set-up, once)
  std::map<long, double> max_by_step;
  std::map<long, double> time_by_step;
};

namespace {

// fix external's callback (post_force, every N steps, on every rank of the instance): the
// largest relative overlap of the touching pairs in the pair style's list. No force is added.
void overlap_callback(void* ptr, LAMMPS_NS::bigint step, int nlocal, int* /*ids*/, double** /*x*/,
                      double** fexternal) {
  auto* st = static_cast<Liggghts::OverlapProbeState*>(ptr);
  for (int i = 0; i < nlocal; ++i) fexternal[i][0] = fexternal[i][1] = fexternal[i][2] = 0.0;
  LAMMPS_NS::LAMMPS* lmp = st->lmp;
  double best = 0.0;
  const LAMMPS_NS::NeighList* list = lmp->force->pair ? lmp->force->pair->list : nullptr;
  if (list) {
    double** x = lmp->atom->x;
    const double* radius = lmp->atom->radius;
    const int* type = lmp->atom->type;
    for (int ii = 0; ii < list->inum; ++ii) {
      const int i = list->ilist[ii];
      const int* jlist = list->firstneigh[i];
      const int jnum = list->numneigh[i];
      for (int jj = 0; jj < jnum; ++jj) {
        const int j = jlist[jj] & NEIGHMASK;
        if (type[i] == st->body_type && type[j] == st->body_type) continue;
        const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
        const double rsum = radius[i] + radius[j];
        const double rsq = dx * dx + dy * dy + dz * dz;
        if (rsq >= rsum * rsum) continue;
        const double delta = rsum - std::sqrt(rsq);
        best = std::max(best, delta / (2 * std::min(radius[i], radius[j])));
      }
    }
  }
  const long s = static_cast<long>(step);
  auto& m = st->max_by_step[s];
  m = std::max(m, best);
  st->time_by_step[s] = lmp->update->get_cur_time();
}

}  // namespace

void Liggghts::start_overlap_probe(long every_steps, int body_type) {
  if (every_steps < 1) every_steps = 1;
  probe_ = std::make_unique<OverlapProbeState>();
  probe_->lmp = static_cast<LAMMPS_NS::LAMMPS*>(lmp_);
  probe_->body_type = body_type;
  command("fix overlap_probe all external pf/callback " + std::to_string(every_steps) + " " +
          std::to_string(every_steps));
  std::string id = "overlap_probe";
  const int ifix = probe_->lmp->modify->find_fix(id.data());
  if (ifix < 0) throw std::runtime_error("LIGGGHTS: fix overlap_probe was not created");
  static_cast<LAMMPS_NS::FixExternal*>(probe_->lmp->modify->fix[ifix])
      ->set_callback(&overlap_callback, probe_.get());
}

std::vector<std::pair<long, double>> Liggghts::overlap_steps() {
  std::vector<std::pair<long, double>> out;
  long n = probe_ ? static_cast<long>(probe_->max_by_step.size()) : 0;
  long n_min = n, n_max = n;
  MPI_Allreduce(MPI_IN_PLACE, &n_min, 1, MPI_LONG, MPI_MIN, comm_);
  MPI_Allreduce(MPI_IN_PLACE, &n_max, 1, MPI_LONG, MPI_MAX, comm_);
  if (n_min != n_max || n == 0) return out;
  std::vector<double> values;
  for (const auto& [step, v] : probe_->max_by_step) values.push_back(v);
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(n), MPI_DOUBLE, MPI_MAX, comm_);
  std::size_t k = 0;
  for (const auto& [step, v] : probe_->max_by_step) out.emplace_back(step, values[k++]);
  return out;
}

void Liggghts::preload_overlap_steps(const std::vector<std::pair<long, double>>& samples) {
  // Their times come from the steps (overlap_samples), so the clock's origin must be set.
  if (!probe_ || !time_origin_)
    throw std::logic_error("preload_overlap_steps needs start_overlap_probe and set_time_origin");
  for (const auto& [step, v] : samples) probe_->max_by_step[step] = v;
}

std::vector<std::pair<double, double>> Liggghts::overlap_samples() {
  std::vector<std::pair<double, double>> out;
  for (const auto& [step, v] : overlap_steps())
    out.emplace_back(time_origin_ ? static_cast<double>(step - *time_origin_) * timestep_s()
                                  : probe_->time_by_step.at(step),
                     v);
  return out;
}

Liggghts::~Liggghts() {
  Quiet quiet;
  if (lmp_) lammps_close(lmp_);
}

void Liggghts::file(const std::string& path) {
  std::string p = path;
  Quiet quiet;
  lammps_file(lmp_, p.data());
}

void Liggghts::command(const std::string& line) {
  std::string l = line;
  Quiet quiet;
  lammps_command(lmp_, l.data());
}

void Liggghts::read_bed_restart(const std::string& restart_path) {
  // liggghts-inputs/impact/setup.in and drop/setup.in, before their read_restart.
  for (const char* line :
       {"atom_style granular", "atom_modify map array", "boundary f f f", "newton off",
        "communicate single vel yes", "units si", "processors * * *"})
    command(line);
  command("read_restart " + restart_path);
}

std::optional<std::string> Liggghts::string(const std::string& name) {
  auto* lmp = static_cast<LAMMPS_NS::LAMMPS*>(lmp_);
  std::string n = name;
  if (lmp->input->variable->find(n.data()) < 0) return std::nullopt;
  const char* value = lmp->input->variable->retrieve(n.data());
  if (!value) return std::nullopt;
  return std::string(value);
}

std::optional<double> Liggghts::number(const std::string& name) {
  const auto text = string(name);
  if (!text) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text->c_str(), &end);
  // "nan" and "inf" parse as such: the caller checks finiteness.
  if (end == text->c_str()) return std::nullopt;
  return v;
}

double Liggghts::fix_vector(const std::string& fix_id, int index) {
  std::string id = fix_id;
  // Global vector of a fix: LIGGGHTS returns a malloc'ed copy.
  auto* p = static_cast<double*>(lammps_extract_fix(lmp_, id.data(), 0, 1, index, 0));
  if (!p) throw std::runtime_error("LIGGGHTS: no global vector for fix " + fix_id);
  const double v = *p;
  std::free(p);
  return v;
}

double Liggghts::time_s() {
  if (time_origin_) return static_cast<double>(step() - *time_origin_) * timestep_s();
  std::string name = "atime";
  return *static_cast<double*>(lammps_extract_global(lmp_, name.data()));
}

double Liggghts::timestep_s() {
  std::string name = "dt";
  return *static_cast<double*>(lammps_extract_global(lmp_, name.data()));
}

long Liggghts::step() {
  std::string name = "ntimestep";
  return static_cast<long>(
      *static_cast<LAMMPS_NS::bigint*>(lammps_extract_global(lmp_, name.data())));
}

long Liggghts::natoms() {
  return lammps_get_natoms(lmp_);
}

Liggghts::LocalAtoms Liggghts::local_atoms() {
  std::string n_nlocal = "nlocal", n_x = "x", n_radius = "radius", n_type = "type";
  const int nlocal = *static_cast<int*>(lammps_extract_global(lmp_, n_nlocal.data()));
  auto** x = static_cast<double**>(lammps_extract_atom(lmp_, n_x.data()));
  auto* radius = static_cast<double*>(lammps_extract_atom(lmp_, n_radius.data()));
  auto* type = static_cast<int*>(lammps_extract_atom(lmp_, n_type.data()));
  LocalAtoms atoms;
  atoms.x.reserve(static_cast<std::size_t>(nlocal));
  for (int i = 0; i < nlocal; ++i) {
    atoms.x.push_back({x[i][0], x[i][1], x[i][2]});
    atoms.radius.push_back(radius[i]);
    atoms.type.push_back(type[i]);
  }
  return atoms;
}

}  // namespace ricochet::dem
