// CPU time of the whole benchmark process, for rates that stay comparable when other
// processes load the machine (wall rates need an idle machine).
#pragma once

#include <sys/resource.h>

namespace slidespec::bench {

/// CPU seconds of this process so far, all threads, user and system.
inline double process_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

}  // namespace slidespec::bench
