// Progress on stderr: a bar with the expected time left on a terminal, one line a minute
// otherwise (logs, batch jobs), nothing with --quiet.
#pragma once

#include <chrono>
#include <mutex>
#include <string>

namespace slidespec::cli {

class Progress {
 public:
  explicit Progress(bool quiet);
  /// Thread-safe and cheap: called from the workers as they go; prints at most a few
  /// times a second (terminal) or once a minute (not a terminal).
  void update(double fraction, const std::string& what);
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  bool quiet_, terminal_;
  Clock::time_point start_, last_;
  std::mutex mutex_;
  bool printed_ = false;
};

}  // namespace slidespec::cli
