// Peak memory of a run does not grow with its duration: the stepper and the
// estimator stream, keeping no trajectory. Each run goes in a child process so that its
// peak resident set is its own (wait4 reports the child's ru_maxrss).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "slidespec/run.hpp"

using namespace slidespec;

namespace {

/// Peak resident set [KiB] of a child process running the reference case over 10..1e3
/// rad/s with 8 realizations of `duration` seconds each, on one thread.
long peak_rss_of_run(double duration) {
  const pid_t child = fork();
  if (child == 0) {
    RunRequest request;
    request.omega_min = 10;
    request.omega_max = 1e3;
    request.duration = duration;
    request.realizations = 8;
    request.threads = 1;
    const RunResult result = run_spectrum(ParameterBuilder("reference").build(), request);
    _exit(result.complete ? 0 : 3);
  }
  int status = 0;
  rusage usage{};
  if (child < 0 || wait4(child, &status, 0, &usage) != child) return -1;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return -2;
  return usage.ru_maxrss;
}

}  // namespace

TEST(RunMemory, PeakResidentSetDoesNotGrowWithDuration) {
  // 200 s at the lowest sub-band's dt = 4 ms is 5e4 steps per lane; ten times that, kept
  // as a trajectory of 8 lanes, would add ~30 MB to a peak of ~8 MB.
  const long short_run = peak_rss_of_run(200);
  const long long_run = peak_rss_of_run(2000);
  ASSERT_GT(short_run, 0);
  ASSERT_GT(long_run, 0);
  EXPECT_LE(long_run, 1.1 * short_run) << "peak RSS " << short_run << " KiB at 200 s, " << long_run << " KiB at 2000 s";
}
