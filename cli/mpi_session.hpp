// MPI for the lifetime of one `dem` subcommand: LIGGGHTS needs it, the other subcommands do not,
// so the program initialises MPI only when a dem subcommand runs (and finalises what it started).
#pragma once

#include <mpi.h>

namespace ricochet::cli {

class MpiSession {
 public:
  MpiSession() {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
      MPI_Init(nullptr, nullptr);
      owner_ = true;
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiSession() {
    if (owner_) MPI_Finalize();
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }  ///< rank in MPI_COMM_WORLD
  int size() const { return size_; }  ///< ranks in MPI_COMM_WORLD

 private:
  bool owner_ = false;
  int rank_ = 0, size_ = 1;
};

}  // namespace ricochet::cli
