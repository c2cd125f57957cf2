#include "taskmap/core/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

// Why st is not a regular file, "" when it is.
std::string notRegular(const struct stat& st) {
  if (S_ISREG(st.st_mode)) return "";
  if (S_ISDIR(st.st_mode)) return "is a directory, not a file";
  if (S_ISFIFO(st.st_mode)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISSOCK(st.st_mode)) return "is a socket, not a regular file";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "is a device, not a regular file";
  return "is not a regular file";
}

}  // namespace

void requireRegularFile(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error(what + " '" + path +
                "': " + (errno == ENOENT ? std::string("no such file") : std::strerror(errno)));
  const std::string why = notRegular(st);
  if (!why.empty()) throw Error(what + " '" + path + "' " + why);
}

std::string readRegularFile(const std::string& path, const std::string& what,
                            std::size_t max_bytes) {
  requireRegularFile(path, what);
  // O_NONBLOCK: should the path have become a FIFO since the check, open does not wait.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw Error(what + " '" + path + "': cannot open (" + std::strerror(errno) + ")");
  struct stat st {};
  std::string why = ::fstat(fd, &st) != 0 ? std::string("cannot stat") : notRegular(st);
  if (why.empty() && static_cast<std::size_t>(st.st_size) > max_bytes)
    why = "is " + std::to_string(st.st_size) + " bytes, more than the limit of " +
          std::to_string(max_bytes);
  std::string bytes;
  if (why.empty()) {
    bytes.resize(static_cast<std::size_t>(st.st_size));
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    bytes.resize(done);
  }
  ::close(fd);
  if (!why.empty()) throw Error(what + " '" + path + "' " + why);
  return bytes;
}

}  // namespace taskmap
