// An advisory lock on a file shared by processes (a campaign file, its claims): flock on a
// separate PATH.lock, so that the locked file itself may be replaced or rewritten.
#pragma once

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <stdexcept>
#include <string>

namespace ricochet::dem {

/// Serialises access to one file across processes (flock on PATH.lock) for the object's lifetime:
/// writers hold it exclusively, readers shared. Used for the campaign file (campaign_store.cpp)
/// and the campaign's claims (campaign_schedule.cpp). Throws std::runtime_error naming PATH.lock
/// when an exclusive lock file cannot be created.
// For the campaign file readers need it too: HDF5 locks the file itself while it is open,
// so a writer's H5Fopen fails outright (rather than waits) while another process reads, which is
// how two groups of an MPI campaign collided when one group counted the index after its append.
// flock locks belong to an open file description, so a process that holds the exclusive lock
// must not take the shared one again (it would wait for itself): append_result reads through
// read_index_unlocked.
class FileLock {
 public:
  enum class Kind { kExclusive, kShared };
  explicit FileLock(const std::string& path, Kind kind = Kind::kExclusive) {
    if (kind == Kind::kExclusive) {
      fd_ = ::open((path + ".lock").c_str(), O_RDWR | O_CREAT, 0644);
      if (fd_ < 0) throw std::runtime_error("cannot create lock file " + path + ".lock");
    } else {
      // A reader creates the lock file too where it can: otherwise the first reader of a file
      // no writer has locked yet (a campaign resumed from its shipped copy) reads unlocked while
      // another rank's first writer creates the lock, and the writer's H5Fopen fails
      // (2026-12-02, every two-rank start of the sand calibration on a new machine). Only where
      // it cannot (shipped data in a read-only folder, which no writer can lock either) is the
      // file read without a lock.
      fd_ = ::open((path + ".lock").c_str(), O_RDONLY);
      if (fd_ < 0) fd_ = ::open((path + ".lock").c_str(), O_RDWR | O_CREAT, 0644);
      if (fd_ < 0) return;
    }
    ::flock(fd_, kind == Kind::kExclusive ? LOCK_EX : LOCK_SH);
  }
  ~FileLock() {
    if (fd_ < 0) return;
    ::flock(fd_, LOCK_UN);
    ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

}  // namespace ricochet::dem
