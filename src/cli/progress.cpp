#include "cli/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace slidespec::cli {

Progress::Progress(bool quiet)
    : quiet_(quiet), terminal_(isatty(STDERR_FILENO) != 0), start_(Clock::now()), last_(start_) {}

void Progress::update(double fraction, const std::string& what) {
  if (quiet_) return;
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;  // another worker is printing: skip, never wait
  const auto now = Clock::now();
  const double since_last = std::chrono::duration<double>(now - last_).count();
  // A log gets a line a minute, the first after ten seconds: a long run is not silent for a minute.
  if (since_last < (terminal_ ? 0.25 : printed_ ? 60.0 : 10.0)) return;
  last_ = now;
  printed_ = true;
  fraction = std::clamp(fraction, 0.0, 1.0);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double left = fraction > 1e-3 ? elapsed * (1 - fraction) / fraction : -1;
  char eta[32];
  if (left < 0)
    std::snprintf(eta, sizeof eta, "--");
  else
    std::snprintf(eta, sizeof eta, "%dm%02ds", int(left) / 60, int(left) % 60);
  if (terminal_) {
    const int width = 30, filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r[%s%s] %5.1f%%  %s  left ~%s   ", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), 100 * fraction, what.c_str(), eta);
  } else {
    std::fprintf(stderr, "slidespec: %5.1f%% %s, %.0f s elapsed, about %s left\n", 100 * fraction, what.c_str(),
                 elapsed, eta);
  }
  std::fflush(stderr);
}

void Progress::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!quiet_ && terminal_ && printed_) std::fprintf(stderr, "\n");
}

}  // namespace slidespec::cli
