// Refusing outputs that would destroy a user's file (output_guard.hpp).
#include "taskmap/core/output_guard.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string_view>
#include <system_error>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kSealMagic = "TASKMAP-SEAL ";
constexpr std::string_view kHdf5Signature = "\x89HDF\r\n\x1a\n";

// The first n bytes of a regular file (non-blocking open; "" when unreadable).
std::string head(const std::string& path, std::size_t n) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "";
  std::string out(n, '\0');
  std::size_t done = 0;
  while (done < n) {
    const ssize_t r = ::pread(fd, out.data() + done, n - done, static_cast<off_t>(done));
    if (r <= 0) break;
    done += static_cast<std::size_t>(r);
  }
  ::close(fd);
  out.resize(done);
  return out;
}

bool hdf5Somewhere(const std::string& bytes) {
  for (std::size_t at = 0; at + kHdf5Signature.size() <= bytes.size(); at = at == 0 ? 512 : 2 * at)
    if (bytes.compare(at, kHdf5Signature.size(), kHdf5Signature) == 0) return true;
  return false;
}

const char* kindName(OutputKind kind) {
  switch (kind) {
    case OutputKind::kTaskMap:
      return "taskmap file (sealed HDF5)";
    case OutputKind::kHdf5:
      return "HDF5 file";
    case OutputKind::kPly:
      return "PLY file";
    case OutputKind::kGlb:
      return "glTF binary (.glb)";
    case OutputKind::kPng:
      return "PNG picture";
    case OutputKind::kDirectory:
      return "directory";
  }
  return "file";
}

}  // namespace

bool looksLike(const std::string& path, OutputKind kind) {
  const std::string b = head(path, 4096);
  auto starts = [&b](std::string_view s) { return b.compare(0, s.size(), s) == 0; };
  switch (kind) {
    case OutputKind::kTaskMap:
      return starts(kSealMagic) || hdf5Somewhere(b);
    case OutputKind::kHdf5:
      return hdf5Somewhere(b) || starts(kSealMagic);
    case OutputKind::kPly:
      return starts("ply");
    case OutputKind::kGlb:
      return starts("glTF");
    case OutputKind::kPng:
      return starts("\x89PNG\r\n\x1a\n");
    case OutputKind::kDirectory:
      return false;
  }
  return false;
}

void checkOutputPath(const std::string& output, const std::vector<std::string>& inputs,
                     OutputKind kind, bool force, const std::string& option) {
  if (output.empty()) return;
  std::error_code ec;
  const fs::file_status st = fs::status(output, ec);  // follows symbolic links
  if (!fs::exists(st)) return;                        // nothing there (or a dangling link)
  for (const std::string& input : inputs) {
    if (input.empty()) continue;
    std::error_code ec2;
    if (fs::equivalent(output, input, ec2) && !ec2)
      throw Error(option + " '" + output + "' is the input '" + input +
                  "' (the same file, or a link to it); writing there would destroy the input: "
                  "choose another output path");
  }
  if (kind == OutputKind::kDirectory) {
    if (!fs::is_directory(st))
      throw Error(option + " '" + output + "' exists and is not a directory");
    return;
  }
  if (!fs::is_regular_file(st))
    throw Error(option + " '" + output + "' exists and is not a regular file (" +
                (fs::is_directory(st) ? "a directory" : "a FIFO, socket or device") +
                "); choose another output path");
  if (force) return;
  struct stat raw {};
  if (::stat(output.c_str(), &raw) == 0 && raw.st_size == 0) return;  // nothing to lose
  if (!looksLike(output, kind))
    throw Error(option + " '" + output + "' exists and is not a " + kindName(kind) +
                "; refusing to replace it (add --force to overwrite it)");
}

}  // namespace taskmap
