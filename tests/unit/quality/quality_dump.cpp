// Helper for tests/python/test_quality_scipy.py: prints random grasps' wrenches and our
// results as JSON, one object per line, so that scipy's ConvexHull can cross-check them.
// Usage: quality_dump <seed> <count>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "quality_fixtures.hpp"
#include "taskmap/quality/grasp_quality.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: quality_dump <seed> <count>\n");
    return 2;
  }
  const auto seed = std::strtoull(argv[1], nullptr, 10);
  const int count = std::atoi(argv[2]);
  for (int s = 0; s < count; ++s) {
    taskmap::Rng rng(seed, static_cast<std::uint64_t>(s));
    const int n = 3 + s % 4;
    taskmap::QualityOptions o;
    o.volume = taskmap::VolumeMode::kAlways;  // scipy's volume is compared for every grasp
    o.friction = rng.uniform(0.3, 1.0);
    if (s % 5 == 4) {
      o.contact_model = taskmap::ContactModel::kSoftFinger;
      o.torsional_friction = 0.01;
    }
    const auto contacts = taskmap::testing::randomContacts(rng, n, s % 2 ? 0.3 : 0.0);
    const Eigen::Vector3d com(0.002, -0.001, 0.0);
    const auto w = taskmap::contactWrenches(contacts, com, 0.05, o);
    const auto r = taskmap::evaluateGrasp(contacts, com, 0.05, o);
    std::printf(
        "{\"set\": %d, \"status\": \"%s\", \"force_closure\": %s, \"epsilon\": %.17g, "
        "\"volume\": %.17g, \"wrenches\": [",
        s, taskmap::toString(r.status), r.force_closure ? "true" : "false", r.epsilon, r.volume);
    for (Eigen::Index j = 0; j < w.cols(); ++j) {
      std::printf("%s[", j ? ", " : "");
      for (int i = 0; i < 6; ++i) std::printf("%s%.17g", i ? ", " : "", w(i, j));
      std::printf("]");
    }
    std::printf("]}\n");
  }
  return 0;
}
