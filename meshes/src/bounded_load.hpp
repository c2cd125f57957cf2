#pragma once
/// @file bounded_load.hpp
/// Private to the meshes stage: parsing an untrusted file in a forked child process with an
/// address-space limit (RLIMIT_AS: the parent's current address space plus
/// max(256 MiB, 20 x the file's size)) and a CPU-time limit, so that no file (a 3MF that makes
/// assimp abort, a 141-byte .x declaring 250 million vertices, a zip bomb) can crash or
/// exhaust the calling process. Used for every mesh assimp reads: objects and hand link meshes.

#include <cstdint>
#include <functional>
#include <string>

#include "mesh_soup.hpp"

namespace taskmap::detail {

/// Limits of one bounded parse of a file of file_bytes bytes.
struct ParseBudget {
  std::uint64_t memory_bytes;  ///< extra address space: max(256 MiB, 20 x file_bytes)
  int cpu_seconds;             ///< 20 s + 1 s per MiB of file
};
ParseBudget parseBudget(std::uint64_t file_bytes);

/// Runs work in a forked child under the budget of a file of file_bytes and returns what work
/// returned. work's Error comes back with its message; a crash, the CPU or wall-time limit, or
/// exhausted memory become Error("<what>: ...") naming the limit. Set TASKMAP_NO_PARSE_CHILD=1
/// to run work in the calling process (debugging).
std::string runBounded(const std::function<std::string()>& work, std::uint64_t file_bytes,
                       const std::string& what);

/// importMeshFile in a bounded child; the soup comes back over a pipe bit for bit.
MeshSoup importMeshFileBounded(const std::string& path, double scale, std::string* format);

}  // namespace taskmap::detail
