// An optimizer that only reads maps: links taskmap::integration alone (see CMakeLists.txt).
#include <iostream>
#include <string>

#include <taskmap/core/error.hpp>
#include <taskmap/integration/task_map.hpp>

int main() {
  try {
    (void)taskmap::TaskMap::load("no_such_map.h5");
  } catch (const taskmap::Error& e) {
    const std::string what = e.what();
    std::cout << "runtime_only: refused as expected: " << what << "\n";
    return what.find("no_such_map.h5") != std::string::npos ? 0 : 1;
  }
  std::cerr << "runtime_only: a missing map was not refused\n";
  return 1;
}
