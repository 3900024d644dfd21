// One LIGGGHTS instance driven through its C library interface (library.h: lammps_open,
// lammps_file, lammps_command, lammps_extract_*), on an MPI communicator.
//
// Every rank of the communicator must make the same calls in the same order (LIGGGHTS commands
// are collective). LIGGGHTS 3.8 ends the process on an input error (error->all calls exit()):
// callers validate what they can before creating an instance, and the campaign records each
// impact as "running" before starting it so that a crash is reported on resume.
#pragma once

#include <mpi.h>

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ricochet::dem {

class Liggghts {
 public:
  /// Opens an instance on `comm`. Screen output goes to `screen_path` and the log to `log_path`
  /// (a NULL screen crashes LIGGGHTS 3.8 at insertion, so the screen is always a file).
  /// `variables` are passed as `-var NAME VALUE` (index variables: they override the decks'
  /// defaults).
  Liggghts(MPI_Comm comm, const std::string& log_path, const std::string& screen_path,
           const std::vector<std::pair<std::string, std::string>>& variables);
  ~Liggghts();
  Liggghts(const Liggghts&) = delete;
  Liggghts& operator=(const Liggghts&) = delete;

  /// Runs an input file (lammps_file).
  void file(const std::string& path);
  /// Runs one command (lammps_command).
  void command(const std::string& line);

  /// Value of an equal-style variable (evaluated now), or of a string/index variable parsed as
  /// a number. nullopt when the variable does not exist.
  std::optional<double> number(const std::string& name);
  /// Value of a string or index variable; nullopt when it does not exist.
  std::optional<std::string> string(const std::string& name);
  /// Element `index` of a global vector computed by fix `fix_id` (e.g. check/timestep/gran).
  double fix_vector(const std::string& fix_id, int index);
  /// Current simulated time [s], time step [s] and step.
  double time_s();
  double timestep_s();
  long step();
  /// Total number of atoms (grains plus block spheres).
  long natoms();

  /// Local atoms of this rank: positions [m], radii [m], types (for the crater profile).
  struct LocalAtoms {
    std::vector<std::array<double, 3>> x;
    std::vector<double> radius;
    std::vector<int> type;
  };
  LocalAtoms local_atoms();

  MPI_Comm comm() const { return comm_; }

 private:
  void* lmp_ = nullptr;
  MPI_Comm comm_;
};

}  // namespace ricochet::dem
