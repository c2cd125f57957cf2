// Built against the install tree by `tools/dev.sh test`: proves the exported package works.
#include <cmath>
#include <iostream>

#include <taskmap/core/pose.hpp>

int main() {
  taskmap::Pose a;
  taskmap::Pose b;
  b.orientation.coeffs() *= -1.0;  // q and -q: the same orientation
  const double d = taskmap::poseDistance(a, b, taskmap::kDefaultRotationScale);
  std::cout << "consumer: distance between q and -q = " << d << "\n";
  return std::abs(d) < 1e-9 ? 0 : 1;
}
