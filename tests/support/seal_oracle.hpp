#pragma once
// Test oracle of the map seal (mapstore/SCHEMA.md, "Seal"), written from the documented format
// independently of mapstore/src/map_seal.cpp: 512 bytes "TASKMAP-SEAL 1\nsha256 <hex>\nbytes
// <n>\n" NUL-padded, then the HDF5 content. Link OpenSSL::Crypto.

#include <openssl/evp.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

namespace taskmap::test {

/// Whole file as bytes ("" when unreadable).
inline std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// Writes bytes to path (truncating).
inline void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Lower-case hex SHA-256 of bytes.
inline std::string sha256Hex(const char* data, std::size_t size) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned length = 0;
  EVP_Digest(data, size, digest, &length, EVP_sha256(), nullptr);
  std::string out;
  char two[3];
  for (unsigned i = 0; i < length; ++i) {
    std::snprintf(two, sizeof two, "%02x", digest[i]);
    out += two;
  }
  return out;
}

/// The 512-byte seal block for content.
inline std::string sealBlock(const std::string& content) {
  std::string block = "TASKMAP-SEAL 1\nsha256 " + sha256Hex(content.data(), content.size()) +
                      "\nbytes " + std::to_string(content.size()) + "\n";
  block.resize(512, '\0');
  return block;
}

/// Re-seals a file that already has the 512-byte user block (after an edit in a test), without
/// validating it: lets a test hand the reader a sealed but invalid map.
inline void forceReseal(const std::string& path) {
  std::string bytes = fileBytes(path);
  if (bytes.size() < 512) return;
  bytes.replace(0, 512, sealBlock(bytes.substr(512)));
  writeBytes(path, bytes);
}

}  // namespace taskmap::test
