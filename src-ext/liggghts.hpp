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
#include <memory>
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
  /// Reads a bed's restart file into this fresh instance, after the set-up the impact and drop
  /// decks give before their own read_restart (granular atoms, fixed boundaries, SI units).
  void read_bed_restart(const std::string& restart_path);

  /// Value of an equal-style variable (evaluated now), or of a string/index variable parsed as
  /// a number. nullopt when the variable does not exist.
  std::optional<double> number(const std::string& name);
  /// Value of a string or index variable; nullopt when it does not exist.
  std::optional<std::string> string(const std::string& name);
  /// Element `index` of a global vector computed by fix `fix_id` (e.g. check/timestep/gran).
  double fix_vector(const std::string& fix_id, int index);
  /// Current simulated time [s], time step [s] and step. After set_time_origin(step0) the time
  /// is (step - step0) x dt, the impact deck's own clock (impact/setup.in, variable t), which a
  /// resumed run keeps; before, LIGGGHTS's elapsed time.
  double time_s();
  void set_time_origin(long step0) { time_origin_ = step0; }
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

  /// The grains' largest overlap, sampled through the runs that follow (collective): every
  /// `every_steps` steps, the largest delta / d over the pairs of the granular pair style's
  /// neighbour list that touch (delta = r_i + r_j - |x_i - x_j| > 0, d = 2 min(r_i, r_j): the
  /// smaller sphere's diameter; pairs of two atoms of `body_type`, the rigid block's own spheres,
  /// are skipped). Defines `fix overlap_probe all external pf/callback N N` whose callback reads
  /// the pair style's list at post_force and adds no force (it zeroes its force array); call it
  /// after a first `run` (the pair style and its list exist) and before the runs to sample. A
  /// step with no touching pair samples 0.
  void start_overlap_probe(long every_steps, int body_type);
  /// The samples so far, (simulated time [s], largest delta / d), reduced over the instance's
  /// ranks (collective). Repeated steps (each run's set-up samples again) keep one sample.
  std::vector<std::pair<double, double>> overlap_samples();
  /// The same samples by step (collective), to carry over a checkpoint; and the samples of an
  /// earlier segment of the run, given back to a resumed run's probe (every rank the same).
  std::vector<std::pair<long, double>> overlap_steps();
  void preload_overlap_steps(const std::vector<std::pair<long, double>>& samples);

  MPI_Comm comm() const { return comm_; }

  struct OverlapProbeState;

 private:
  void* lmp_ = nullptr;
  MPI_Comm comm_;
  std::unique_ptr<OverlapProbeState> probe_;
  std::optional<long> time_origin_;
};

}  // namespace ricochet::dem
