#pragma once
// What the sampler build tests share (antipodal_build_test, palm_enclose_build_test): the real
// inputs of tests/data/real, loaded once, and the small build that compares samplers by trial
// counts.
#include <map>
#include <string>

#include "taskmap/builder/map_builder.hpp"

namespace taskmap::testing {

/// tests/data/real/<path> loaded once (objects: a mesh; hands: a URDF beside its sidecar).
inline const ObjectModel& realObject(const std::string& path) {
  static std::map<std::string, ObjectModel> loaded;
  auto it = loaded.find(path);
  if (it == loaded.end())
    it =
        loaded.emplace(path, ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/" + path)).first;
  return it->second;
}

/// The hand of tests/data/real/<path>, loaded once.
inline const HandModel& realHand(const std::string& path) {
  static std::map<std::string, HandModel> loaded;
  auto it = loaded.find(path);
  if (it == loaded.end())
    it = loaded.emplace(path, HandModel::load(std::string(TEST_DATA_DIR) + "/real/" + path)).first;
  return it->second;
}

/// A build of `valid` grasps with sampler `kind` on `threads` threads in blocks of `block`
/// (seed 3, no clustering, a generous trial budget).
inline BuildOptions samplerBuild(SamplerKind kind, int threads, std::uint64_t valid, int block) {
  BuildOptions o;
  o.seed = 3;
  o.valid_target = valid;
  o.max_trials = 20000;
  o.threads = threads;
  o.block_size = block;
  o.sampler.kind = kind;
  o.cluster = false;
  return o;
}

}  // namespace taskmap::testing
