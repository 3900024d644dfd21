// MPI for the lifetime of one `dem` subcommand: LIGGGHTS needs it, the other subcommands do not,
// so the program initialises MPI only when a dem subcommand runs (and finalises what it started).
#pragma once

#include <mpi.h>

#include <exception>
#include <iostream>
#include <string>

#include "common/error.hpp"

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
  /// Runs `body` on this rank. With several ranks, an exception on one of them must not leave
  /// the others waiting in a collective for ever (MPI_Finalize, run while the exception
  /// unwinds, waits for them, and the error is never printed): the failing rank prints its
  /// error, naming itself, and aborts the whole job with the CLI's exit status (2 bad input, 1
  /// runtime failure; docs/commands/README.md). On one rank the exception propagates as for any
  /// other command.
  template <class F>
  void run(F&& body) {
    if (size_ == 1) {
      body();
      return;
    }
    int status = 0;
    try {
      body();
      return;
    } catch (const InputError& e) {
      report(e.what());
      status = 2;
    } catch (const std::exception& e) {
      report(e.what());
      status = 1;
    }
    MPI_Abort(MPI_COMM_WORLD, status);
  }
  int rank() const { return rank_; }  ///< rank in MPI_COMM_WORLD
  int size() const { return size_; }  ///< ranks in MPI_COMM_WORLD

 private:
  // One write per message, so that the lines of ranks failing together do not interleave.
  void report(const char* what) const {
    const std::string line = "ricochet: error (MPI rank " + std::to_string(rank_) + " of " +
                             std::to_string(size_) + "): " + what + "\n";
    std::cerr.write(line.data(), static_cast<std::streamsize>(line.size()));
    std::cerr.flush();
  }

  bool owner_ = false;
  int rank_ = 0, size_ = 1;
};

}  // namespace ricochet::cli
