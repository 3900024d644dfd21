#include "common/progress.hpp"

#include <unistd.h>

#include <cstdio>

#include "common/clock.hpp"

namespace ricochet {

Progress::Progress(std::string label, std::size_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      active_(enabled && isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() {
  finish();
}

void Progress::advance(std::size_t n) {
  if (!active_) return;
  std::lock_guard lock(mutex_);
  done_ += n;
  draw_locked(done_ >= total_);
}

void Progress::status(const std::string& text) {
  if (!active_) return;
  std::lock_guard lock(mutex_);
  status_ = text;
  draw_locked(false);
}

void Progress::draw_locked(bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double frac = total_ ? static_cast<double>(done_) / static_cast<double>(total_) : 1.0;
  const int width = 30;
  const int filled = static_cast<int>(frac * width);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = frac > 0 ? elapsed * (1.0 - frac) / frac : 0.0;
  std::fprintf(stderr, "\r%s [%.*s%*s] %zu/%zu %5.1fs eta %5.1fs %s\033[K", label_.c_str(), filled,
               "##############################", width - filled, "", done_, total_, elapsed, eta,
               status_.c_str());
  std::fflush(stderr);
}

void Progress::finish() {
  if (!active_ || finished_) return;
  std::lock_guard lock(mutex_);
  finished_ = true;
  const double elapsed = seconds_since(start_);
  std::fprintf(stderr, "\r%s: %zu/%zu done in %.2f s\033[K\n", label_.c_str(), done_, total_,
               elapsed);
}

}  // namespace ricochet
