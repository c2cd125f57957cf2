// The seal of a task map file: magic, version, SHA-256 and length of the HDF5 content, in the
// HDF5 user block (mapstore/SCHEMA.md, "Seal"). Verified before HDF5 parses anything.
#include "map_seal.hpp"

#include <fcntl.h>
#include <openssl/evp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <utility>

#include "taskmap/core/error.hpp"

namespace taskmap::seal {
namespace {

constexpr std::string_view kMagic = "TASKMAP-SEAL ";
constexpr int kSealVersion = 1;
constexpr std::string_view kHdf5Signature = "\x89HDF\r\n\x1a\n";
constexpr const char* kResealHint =
    "; if the change was deliberate and you trust the file, re-seal it with `taskmap seal FILE` "
    "(Python: taskmap.seal(path))";

// Owning file descriptor.
struct Fd {
  int fd;
  explicit Fd(int f) : fd(f) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

std::string hex(const unsigned char* digest, unsigned length) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (unsigned i = 0; i < length; ++i) {
    out += digits[digest[i] >> 4];
    out += digits[digest[i] & 15];
  }
  return out;
}

std::string sha256(const char* data, std::size_t size) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned length = 0;
  if (EVP_Digest(data, size, digest, &length, EVP_sha256(), nullptr) != 1)
    throw Error("SHA-256 computation failed (OpenSSL)");
  return hex(digest, length);
}

// Reads exactly size bytes at offset; false on a short read (the file changed under us).
bool readAt(int fd, char* out, std::size_t size, off_t offset) {
  while (size > 0) {
    const ssize_t n = ::pread(fd, out, size, offset);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    out += n;
    size -= static_cast<std::size_t>(n);
    offset += n;
  }
  return true;
}

Fd openForReading(const std::string& path, std::size_t* size) {
  // O_NONBLOCK: opening a FIFO does not wait for a writer; fstat then refuses it.
  Fd f(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (f.fd < 0) throw Error(std::string("cannot open the file (") + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(f.fd, &st) != 0 || !S_ISREG(st.st_mode))
    throw Error(S_ISFIFO(st.st_mode) ? "is a FIFO (named pipe), not a regular file"
                                     : "not a regular file (a directory or a device?)");
  *size = static_cast<std::size_t>(st.st_size);
  return Fd(std::exchange(f.fd, -1));
}

bool hdf5At(const std::string& bytes, std::size_t offset) {
  return bytes.size() >= offset + kHdf5Signature.size() &&
         bytes.compare(offset, kHdf5Signature.size(), kHdf5Signature) == 0;
}

// The parsed seal text: "TASKMAP-SEAL <version>\nsha256 <hex>\nbytes <n>\n", NUL-padded.
struct Parsed {
  int version = 0;
  std::string sha256;
  unsigned long long bytes = 0;
};

Parsed parse(const std::string& block) {
  Parsed p;
  char digest[65] = {};
  int consumed = 0;
  const std::size_t nul = block.find('\0');
  const std::string text = block.substr(0, nul);
  if (nul == std::string::npos || block.find_first_not_of('\0', nul) != std::string::npos)
    throw Error("its seal (the first 512 bytes) is damaged; the file is corrupt");
  if (std::sscanf(text.c_str(), "TASKMAP-SEAL %4d\nsha256 %64[0-9a-f]\nbytes %19llu\n%n",
                  &p.version, digest, &p.bytes, &consumed) != 3 ||
      consumed != static_cast<int>(text.size()))
    throw Error("its seal (the first 512 bytes) is damaged; the file is corrupt");
  p.sha256 = digest;
  // Exactly the text the writer produces (sscanf alone would accept other spacing).
  const std::string canonical = std::string(kMagic) + std::to_string(p.version) + "\nsha256 " +
                                p.sha256 + "\nbytes " + std::to_string(p.bytes) + "\n";
  if (p.sha256.size() != 64 || canonical != text)
    throw Error("its seal (the first 512 bytes) is damaged; the file is corrupt");
  return p;
}

}  // namespace

std::string blockFor(const char* content, std::size_t size) {
  std::string block = std::string(kMagic) + std::to_string(kSealVersion) + "\nsha256 " +
                      sha256(content, size) + "\nbytes " + std::to_string(size) + "\n";
  block.resize(kSealBytes, '\0');
  return block;
}

bool hasHdf5Signature(const std::string& bytes) {
  if (hdf5At(bytes, 0)) return true;
  for (std::size_t at = kSealBytes; at < bytes.size(); at *= 2)
    if (hdf5At(bytes, at)) return true;
  return false;
}

std::string readWhole(const std::string& path, std::size_t max_bytes) {
  std::size_t size = 0;
  Fd f = openForReading(path, &size);
  if (size > max_bytes)
    throw Error("file of " + std::to_string(size) + " bytes is larger than the limit of " +
                std::to_string(max_bytes));
  std::string bytes(size, '\0');
  if (!readAt(f.fd, bytes.data(), size, 0)) throw Error("the file changed while being read");
  return bytes;
}

std::string readVerified(const std::string& path) {
  return readVerified(path, "task map", kResealHint);
}

std::string readVerified(const std::string& path, const std::string& kind,
                         const std::string& hint) {
  std::size_t size = 0;
  Fd f = openForReading(path, &size);
  std::string bytes(std::min(size, kSealBytes), '\0');
  if (!readAt(f.fd, bytes.data(), bytes.size(), 0))
    throw Error("the file changed while being read");
  if (bytes.compare(0, kMagic.size(), kMagic) != 0) {
    if (hdf5At(bytes, 0))
      throw Error(
          "the file has no taskmap seal: HDF5 written by another tool (or by taskmap before "
          "schema 2), so its integrity cannot be checked" +
          hint);
    throw Error("not a " + kind + ": no taskmap seal at the start of the file (" +
                std::to_string(size) + " bytes; truncated, damaged or another format)");
  }
  if (size < kSealBytes)
    throw Error("truncated: " + std::to_string(size) + " bytes, shorter than the seal itself");
  const Parsed p = parse(bytes);
  if (p.version > kSealVersion)
    throw Error("sealed by a newer taskmap (seal version " + std::to_string(p.version) +
                "); upgrade taskmap to read it");
  if (p.version < 1) throw Error("its seal (the first 512 bytes) is damaged (version 0)");
  const std::size_t content = size - kSealBytes;
  if (content != p.bytes)
    throw Error("its length does not match its seal (" + std::to_string(content) +
                " bytes follow the seal, which declares " + std::to_string(p.bytes) +
                "): " + (content < p.bytes ? "truncated" : "extended") +
                ", or changed by another tool" + hint);
  bytes.resize(size);
  if (!readAt(f.fd, bytes.data() + kSealBytes, content, static_cast<off_t>(kSealBytes)))
    throw Error("the file changed while being read");
  if (sha256(bytes.data() + kSealBytes, content) != p.sha256)
    throw Error(
        "the content does not match its seal (SHA-256 differs): the file is damaged, or was "
        "changed by another tool" +
        hint);
  if (!hdf5At(bytes, kSealBytes)) throw Error("the sealed content is not an HDF5 file");
  return bytes;
}

void stampFile(const std::string& path) {
  std::string bytes = readWhole(path, static_cast<std::size_t>(-1));
  if (bytes.size() < kSealBytes || !hdf5At(bytes, kSealBytes))
    throw Error("the written file has no user block for the seal");
  const std::string block = blockFor(bytes.data() + kSealBytes, bytes.size() - kSealBytes);
  Fd f(::open(path.c_str(), O_WRONLY | O_CLOEXEC));
  if (f.fd < 0 || ::pwrite(f.fd, block.data(), block.size(), 0) != static_cast<ssize_t>(kSealBytes))
    throw Error("cannot write the seal (disk full?)");
  if (::fsync(f.fd) != 0) throw Error("cannot flush the file (disk full?)");
}

std::string resealed(std::string bytes) {
  if (hdf5At(bytes, 0)) {
    std::string out = blockFor(bytes.data(), bytes.size());
    out += bytes;
    return out;
  }
  if (bytes.compare(0, kMagic.size(), kMagic) != 0 || !hdf5At(bytes, kSealBytes))
    throw Error(hdf5At(bytes, kSealBytes) || hdf5At(bytes, 2 * kSealBytes)
                    ? "the file's HDF5 user block is not a taskmap seal; refusing to overwrite it"
                    : "not an HDF5 file (no HDF5 signature at offset 0 or 512)");
  const std::string block = blockFor(bytes.data() + kSealBytes, bytes.size() - kSealBytes);
  bytes.replace(0, kSealBytes, block);
  return bytes;
}

std::string sha256Hex(const std::string& bytes) {
  return sha256(bytes.data(), bytes.size());
}

}  // namespace taskmap::seal
