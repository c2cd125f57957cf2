#pragma once
/// @file input_file.hpp
/// Input paths checked before anything opens them: opening a FIFO blocks until a writer comes,
/// reading a device or a directory never ends or fails obscurely. Every loader of the library
/// (meshes, hand URDFs and sidecars, robot URDFs, scenes, maps, ACRONYM files) calls
/// requireRegularFile first, so the C++ API, the Python module and the tool refuse them alike.

#include <cstddef>
#include <string>

namespace taskmap {

/// Throws Error("<what> '<path>': ...") unless path names an existing regular file (symbolic
/// links followed): "no such file", "is a directory", "is a FIFO (named pipe), not a regular
/// file", "is a device ...". Does not open the file.
void requireRegularFile(const std::string& path, const std::string& what);

/// Reads a regular file whole (requireRegularFile, then a non-blocking open checked again with
/// fstat). Throws Error naming the file when it is not one, cannot be read or is larger than
/// max_bytes.
std::string readRegularFile(const std::string& path, const std::string& what,
                            std::size_t max_bytes = static_cast<std::size_t>(-1));

}  // namespace taskmap
