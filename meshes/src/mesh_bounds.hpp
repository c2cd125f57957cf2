#pragma once
/// @file mesh_bounds.hpp
/// Private to the meshes stage: checks what a mesh file's header declares (vertex, face and
/// element counts of OFF, PLY, binary STL) against the file's size before assimp reads it.
/// assimp reserves what a header says, so a 300-byte file declaring 10^11 vertices would
/// otherwise allocate gigabytes before failing.

#include <cstdint>
#include <string>

namespace taskmap::detail {

/// Throws Error("mesh file '<path>': ...") when the header declares more elements than
/// `file_size` bytes can hold (every element needs at least one byte per value in text
/// formats, its fixed size in binary ones), or when the header is malformed in a way that
/// would make assimp guess. Other formats (OBJ, ASCII STL, COLLADA, ...) are line- or
/// tag-based: assimp's memory grows with the content, so only the size cap applies.
/// @param ext lower-case file extension ("off", "ply", "stl", ...).
void checkDeclaredSizes(const std::string& path, const std::string& ext, std::uintmax_t file_size);

/// Largest mesh file accepted (bytes).
constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t{2} << 30;

}  // namespace taskmap::detail
