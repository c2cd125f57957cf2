#pragma once
/// @file output_guard.hpp
/// No command replaces a user's file by mistake: an output path that is one of the command's
/// inputs (the same path, a hard link to it, or a symbolic link to it) is refused, and an
/// existing output that does not look like what the command writes (a sealed task map, an HDF5
/// file, a PLY, GLB or PNG file) is replaced only with --force. Run before any work.

#include <string>
#include <vector>

namespace taskmap {

/// What a command writes at its output path, recognised by the first bytes of an existing file.
enum class OutputKind {
  kTaskMap,    ///< sealed HDF5 task map (build, import), or a trajectory file (reach -o)
  kHdf5,       ///< any HDF5 file (export --format acronym)
  kPly,        ///< "ply" header
  kGlb,        ///< glTF binary ("glTF")
  kPng,        ///< PNG picture
  kDirectory,  ///< a data-set directory (a directory, or nothing)
};

/// Throws Error naming both paths when output is one of inputs (same file, hard or symbolic
/// link; inputs that do not exist are skipped) and, unless force, when output exists and is
/// not a regular file, or is a non-empty file whose first bytes are not of kind.
/// @param option the option that names the output, e.g. "-o", for the messages.
void checkOutputPath(const std::string& output, const std::vector<std::string>& inputs,
                     OutputKind kind, bool force, const std::string& option = "-o");

/// True when the file at path starts like kind (see OutputKind); false when it cannot be read.
bool looksLike(const std::string& path, OutputKind kind);

}  // namespace taskmap
