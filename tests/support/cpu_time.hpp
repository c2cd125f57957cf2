#pragma once
// CPU time for the tests that bound the work of a refusal (a huge URDF refused before parsing, a
// mesh in the wrong units refused while loading): CPU seconds, not wall time, so a loaded machine
// does not fail them; a bound here guards against a hang or a blow-up, it does not measure speed
// (benchmarks do, tests/bench).

#include <sys/resource.h>

namespace taskmap::testing {

/// User + system CPU seconds of `who` (RUSAGE_SELF: this process, all threads; RUSAGE_CHILDREN:
/// the children it waited for, with theirs).
inline double cpuSeconds(int who = RUSAGE_SELF) {
  rusage r{};
  getrusage(who, &r);
  return static_cast<double>(r.ru_utime.tv_sec + r.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(r.ru_utime.tv_usec + r.ru_stime.tv_usec);
}

}  // namespace taskmap::testing
