// Meshes parsed in a bounded child process (bounded_load.hpp).
#include "bounded_load.hpp"

#include <sys/stat.h>

#include <cstring>

#include "taskmap/core/bounded_child.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::detail {

MeshSoup importMeshFileBounded(const std::string& path, double scale, std::string* format) {
  struct stat st {};
  const std::uint64_t size =
      ::stat(path.c_str(), &st) == 0 ? static_cast<std::uint64_t>(st.st_size) : 0;
  const std::string bytes = runBounded(
      [&]() {
        std::string fmt;
        const MeshSoup soup = importMeshFile(path, scale, &fmt);
        // format, points (x y z doubles), faces (3 ints), each count first.
        std::string out;
        const auto put = [&out](const void* data, std::size_t n) {
          out.append(static_cast<const char*>(data), n);
        };
        const std::uint64_t counts[3] = {fmt.size(), soup.points.size(), soup.faces.size()};
        put(counts, sizeof counts);
        put(fmt.data(), fmt.size());
        for (const Eigen::Vector3d& p : soup.points) put(p.data(), 3 * sizeof(double));
        for (const auto& f : soup.faces) put(f.data(), 3 * sizeof(int));
        return out;
      },
      size, "mesh file '" + path + "'");
  std::uint64_t counts[3] = {0, 0, 0};
  if (bytes.size() < sizeof counts) throw Error("mesh file '" + path + "': parser reply torn");
  std::memcpy(counts, bytes.data(), sizeof counts);
  const std::uint64_t expect =
      sizeof counts + counts[0] + counts[1] * 3 * sizeof(double) + counts[2] * 3 * sizeof(int);
  if (bytes.size() != expect) throw Error("mesh file '" + path + "': parser reply torn");
  const char* at = bytes.data() + sizeof counts;
  if (format != nullptr) *format = std::string(at, counts[0]);
  at += counts[0];
  MeshSoup soup;
  soup.points.resize(counts[1]);
  for (Eigen::Vector3d& p : soup.points) {
    std::memcpy(p.data(), at, 3 * sizeof(double));
    at += 3 * sizeof(double);
  }
  soup.faces.resize(counts[2]);
  for (auto& f : soup.faces) {
    std::memcpy(f.data(), at, 3 * sizeof(int));
    at += 3 * sizeof(int);
  }
  return soup;
}

}  // namespace taskmap::detail
