// One run at a time on a directory or an output (run_lock.hpp).
#include "taskmap/core/run_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "taskmap/core/error.hpp"

namespace taskmap {

RunLock::RunLock(std::string lock_path, const std::string& what) : path_(std::move(lock_path)) {
  // A lock taken on a file that the previous holder unlinked meanwhile is no lock: retry.
  for (int attempt = 0; attempt < 5; ++attempt) {
    if (tryLock(what)) return;
  }
  throw Error("cannot take the lock file '" + path_ + "' (it keeps being replaced)");
}

bool RunLock::tryLock(const std::string& what) {
  // O_NOFOLLOW and a regular-file check: the lock file is never a link planted elsewhere.
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
  if (fd_ < 0)
    throw Error("cannot create lock file '" + path_ + "' (" + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw Error("lock file '" + path_ + "' is not a regular file");
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    char buffer[32] = {};
    const ssize_t n = ::pread(fd_, buffer, sizeof buffer - 1, 0);
    std::string pid = n > 0 ? std::string(buffer, static_cast<std::size_t>(n)) : "unknown";
    while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
    ::close(fd_);
    fd_ = -1;
    throw Error(what + " is in use by another taskmap run (PID " + pid + ", lock file '" + path_ +
                "'); wait for it to finish");
  }
  struct stat now {};
  if (::stat(path_.c_str(), &now) != 0 || now.st_ino != st.st_ino || now.st_dev != st.st_dev) {
    ::close(fd_);
    fd_ = -1;
    return false;
  }
  const std::string me = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, me.data(), me.size(), 0) < 0) {
    // The PID is only for the message of a second run; the lock itself holds.
  }
  return true;
}

RunLock::~RunLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while still holding it: nothing is left behind
  ::close(fd_);
}

}  // namespace taskmap
