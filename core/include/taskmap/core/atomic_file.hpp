#pragma once
/// @file atomic_file.hpp
/// Writing files so that a crash, a kill or an error never leaves a partial file at the
/// destination: write a temporary file beside it, then rename it over the destination.

#include <string>

namespace taskmap {

/// Moves the finished temporary file `tmp` over `path` (atomic within one filesystem). On
/// failure removes `tmp` and throws Error("<what>: rename failed (<reason>)").
/// @param what start of the error message, naming the file, e.g. "cannot write picture 'a.png'".
void commitTemporaryFile(const std::string& tmp, const std::string& path, const std::string& what);

/// Writes `bytes` to `path` through a temporary file beside it and commitTemporaryFile. On
/// failure throws Error starting with `what`; nothing partial is left at `path`.
void writeFileAtomically(const std::string& path, const std::string& bytes,
                         const std::string& what);

}  // namespace taskmap
