#pragma once
/// @file bounded_child.hpp
/// Parsing an untrusted file in a forked child process with an address-space limit (RLIMIT_AS:
/// the caller's current address space plus max(256 MiB, 20 x the file's size)) and a CPU-time
/// limit, so that no file can crash or exhaust the calling process (C++ API, Python module and
/// tool alike). Under AddressSanitizer, whose shadow memory needs terabytes of address space,
/// the same budget is a data limit instead (RLIMIT_DATA over the caller's VmData), and the
/// sanitizer's out-of-memory report counts as exhausted memory. The meshes stage parses every mesh
/// this way (assimp), mapstore the HDF5 of a file it is asked to seal.

#include <cstdint>
#include <functional>
#include <string>

namespace taskmap {

/// Limits of one bounded run (parseBudget: of a parse of a file of file_bytes bytes).
struct ParseBudget {
  std::uint64_t memory_bytes;  ///< extra address space: max(256 MiB, 20 x file_bytes)
  int cpu_seconds;             ///< 20 s + 1 s per MiB of file (at most an hour)
};
/// The budget of parsing a file of file_bytes bytes (the fields' comments above).
ParseBudget parseBudget(std::uint64_t file_bytes);

/// Runs work in a forked child under the budget of a file of file_bytes and returns what work
/// returned. work's exceptions come back as Error with their message; a crash, the CPU or
/// wall-time limit (2 x CPU + 10 s), or exhausted memory become Error("<what>: ...") naming the
/// limits. Set TASKMAP_NO_PARSE_CHILD=1 to run work in the calling process (debugging). In a
/// multi-threaded caller, work must not need a lock another thread may hold (the wall-time
/// limit ends such a child).
std::string runBounded(const std::function<std::string()>& work, std::uint64_t file_bytes,
                       const std::string& what);

/// Runs work in a forked child under explicit limits: budget.memory_bytes of memory beyond the
/// caller's (address space; data under AddressSanitizer, as above) and budget.cpu_seconds of
/// CPU (wall time 2 x CPU + 10 s), for work that is more than one parse (`taskmap import` and
/// `taskmap seal` take them as --memory-gib and --cpu-seconds). Returns what work returned;
/// failures are the Errors of the overload above, the limits named as "the limits are <memory>
/// MiB of memory and <cpu> s of CPU". Throws Error when a limit is not positive.
std::string runBounded(const std::function<std::string()>& work, const ParseBudget& budget,
                       const std::string& what);

}  // namespace taskmap
