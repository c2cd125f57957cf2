#pragma once
// Private to mapstore: the seal of a task map file (mapstore/SCHEMA.md, "Seal"). The first
// kSealBytes of the file are the HDF5 user block; they hold a short text naming the SHA-256 and
// the length of everything after them. Nothing here calls HDF5: the seal is checked before
// HDF5 sees a byte of the file.

#include <cstddef>
#include <string>

namespace taskmap::seal {

/// Size of the user block that holds the seal (HDF5 needs a power of two >= 512).
constexpr std::size_t kSealBytes = 512;

/// Reads the file whole and verifies its seal; returns its bytes, seal included. The length
/// is checked against the seal before the content is read. Throws Error (without the path)
/// saying what is wrong: missing, too short, no seal, damaged seal, newer seal version,
/// truncated or extended, content not matching the seal.
std::string readVerified(const std::string& path);
/// readVerified for a sealed file of another kind: messages call it `kind` (e.g. "trajectory
/// file") and end the damaged/unsealed cases with `hint` (what to do; "" for nothing).
std::string readVerified(const std::string& path, const std::string& kind, const std::string& hint);

/// True when bytes hold an HDF5 superblock signature where HDF5 looks for one: offset 0, 512,
/// 1024, 2048, ... (after a user block).
bool hasHdf5Signature(const std::string& bytes);

/// SHA-256 of bytes as 64 lower-case hex digits.
std::string sha256Hex(const std::string& bytes);

/// Reads the file whole (any content), refusing files larger than max_bytes.
std::string readWhole(const std::string& path, std::size_t max_bytes);

/// The seal block (kSealBytes) for content, the bytes that follow it in the file.
std::string blockFor(const char* content, std::size_t size);

/// Writes the seal over the first kSealBytes of the file at path (the HDF5 user block that
/// the writer reserved) for the rest of the file, then fsyncs it.
void stampFile(const std::string& path);

/// bytes of an HDF5 file, returned with a fresh seal in front: a file without a user block
/// gets one prepended (HDF5 finds the superblock at offset kSealBytes), a file whose user
/// block holds a taskmap seal (valid or not) gets it replaced. Refuses other user blocks.
std::string resealed(std::string bytes);

}  // namespace taskmap::seal
