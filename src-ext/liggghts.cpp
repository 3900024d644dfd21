#include "liggghts.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

// LIGGGHTS headers (libliggghts-dev): the C interface plus the Variable class, whose retrieve()
// returns any variable's value as text (the C interface cannot tell a variable's style).
#include <input.h>
#include <lammps.h>
#include <library.h>
#include <variable.h>

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
