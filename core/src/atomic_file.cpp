#include "taskmap/core/atomic_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "taskmap/core/error.hpp"

namespace taskmap {

void commitTemporaryFile(const std::string& tmp, const std::string& path, const std::string& what) {
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    const std::string why = ec.message();
    std::filesystem::remove(tmp, ec);
    throw Error(what + ": rename failed (" + why + ")");
  }
}

void writeFileAtomically(const std::string& path, const std::string& bytes,
                         const std::string& what) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(what + ": cannot create " + tmp);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw Error(what + ": write failed (disk full?)");
    }
  }
  commitTemporaryFile(tmp, path, what);
}

}  // namespace taskmap
