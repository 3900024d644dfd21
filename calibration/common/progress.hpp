// Progress reporting for long runs: a bar on a terminal, nothing when stderr is not a terminal.
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace ricochet {

/// Thread-safe progress bar on stderr. Draws only when stderr is a terminal (isatty) and
/// `enabled` is true, so logs and CI output stay clean. Redraws at most ~10 times a second.
class Progress {
 public:
  Progress(std::string label, std::size_t total, bool enabled = true);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Adds `n` finished units of work.
  void advance(std::size_t n = 1);
  /// Sets a short status text shown after the bar (e.g. the current impact id).
  void status(const std::string& text);
  /// Clears the bar line and prints a one-line summary (only on a terminal).
  void finish();
  bool active() const { return active_; }

 private:
  void draw_locked(bool force);

  std::string label_;
  std::size_t total_;
  std::size_t done_ = 0;
  bool active_;
  bool finished_ = false;
  std::string status_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex mutex_;
};

}  // namespace ricochet
