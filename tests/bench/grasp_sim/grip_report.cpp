// grip_report: per hand x object, build a task map in process and report what coupled closing
// and fingertip grasps change: valid (force-closure) rate, share of stored grasps touched by two
// or more fingers, clusters, and the outcome counts. Not a timing benchmark.
//
//   grip_report [--trials N] [--valid N] [--threads N] [--no-centre] [--grasp palm|fingertip]
//               [--keep-invalid]
//               HAND ... -- OBJECT ...
// HAND: path/to/hand.urdf or path/to/hand.urdf@path/to/sidecar.hand.json (label = file stem);
// OBJECT: path/to/mesh[@scale]. A hand or object that fails to load is reported and skipped.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/error.hpp"

namespace {

using taskmap::BuildOptions;
using taskmap::HandModel;
using taskmap::ObjectModel;

struct Row {
  std::string hand, object;
  double valid_rate = 0.0, two_finger = 0.0;
  std::size_t stored = 0, clusters = 0;
  std::string outcomes;
};

std::string stem(const std::string& path) {
  return std::filesystem::path(path).stem().string();
}

// Stored grasps whose contacts lie on two or more fingers, as a share of the stored grasps.
double twoFingerShare(const taskmap::TaskMapData& map, const HandModel& hand) {
  const auto& g = map.grasps;
  if (g.size() == 0) return 0.0;
  std::size_t two = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    std::set<int> fingers;
    for (auto k = g.contact_offsets[i]; k < g.contact_offsets[i + 1]; ++k) {
      const int l = g.contact_links[static_cast<std::size_t>(k)];
      if (l >= 0) {
        const int f = hand.links()[static_cast<std::size_t>(l)].finger;
        if (f >= 0) fingers.insert(f);
      }
    }
    two += fingers.size() >= 2;
  }
  return static_cast<double>(two) / static_cast<double>(g.size());
}

Row run(const HandModel& hand, const std::string& hand_label, const ObjectModel& object,
        const std::string& object_label, const BuildOptions& options) {
  const taskmap::BuildResult r = taskmap::buildMap(object, hand, options);
  Row row;
  row.hand = hand_label;
  row.object = object_label;
  const auto& s = r.map.sampling;
  const auto fc = s.outcomes.count("force_closure") ? s.outcomes.at("force_closure") : 0;
  row.valid_rate = s.trials ? static_cast<double>(fc) / static_cast<double>(s.trials) : 0.0;
  row.stored = r.map.grasps.size();
  row.two_finger = twoFingerShare(r.map, hand);
  row.clusters = r.map.clustering ? r.map.clustering->clusters.size() : 0;
  for (const auto& [name, count] : s.outcomes)
    row.outcomes += " " + name + "=" + std::to_string(count);
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  BuildOptions options;
  options.max_trials = 4000;
  options.valid_target = 400;
  options.threads = 2;
  std::vector<std::string> hands, objects;
  bool after_sep = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
    if (a == "--trials")
      options.max_trials = std::stoull(next());
    else if (a == "--valid")
      options.valid_target = std::stoull(next());
    else if (a == "--threads")
      options.threads = std::stoi(next());
    else if (a == "--keep-invalid")  // 2-finger% then covers every completed trial
      options.stored = taskmap::StoredGrasps::kAllCompleted;
    else if (a == "--no-centre")
      options.simulation.centre_coupled = false;
    else if (a == "--grasp")
      options.simulation.grasp_mode =
          next() == "fingertip" ? taskmap::GraspMode::kFingertip : taskmap::GraspMode::kPalm;
    else if (a == "--")
      after_sep = true;
    else
      (after_sep ? objects : hands).push_back(a);
  }
  if (hands.empty() || objects.empty()) {
    std::cerr << "usage: grip_report [options] HAND[@SIDECAR] ... -- OBJECT[@SCALE] ...\n";
    return 2;
  }
  std::printf("%-22s %-16s %9s %7s %10s %8s  outcomes\n", "hand", "object", "valid%", "stored",
              "2-finger%", "clusters");
  for (const auto& h : hands) {
    const auto at = h.find('@');
    const std::string urdf = h.substr(0, at);
    const std::string sidecar = at == std::string::npos ? "" : h.substr(at + 1);
    const std::string label = stem(sidecar.empty() ? urdf : sidecar);
    HandModel hand;
    try {
      hand = HandModel::load(urdf, sidecar);
    } catch (const taskmap::Error& e) {
      std::printf("%-22s does not load: %s\n", label.c_str(), e.what());
      continue;
    }
    for (const auto& o : objects) {
      const auto oat = o.find('@');
      const std::string mesh = o.substr(0, oat);
      const double scale = oat == std::string::npos ? 1.0 : std::atof(o.substr(oat + 1).c_str());
      try {
        const ObjectModel object = ObjectModel::load(mesh, taskmap::MeshLoadOptions{scale});
        const Row r = run(hand, label, object, stem(mesh).substr(0, 16), options);
        std::printf("%-22s %-16s %8.2f%% %7zu %9.1f%% %8zu  %s\n", r.hand.c_str(), r.object.c_str(),
                    100.0 * r.valid_rate, r.stored, 100.0 * r.two_finger, r.clusters,
                    r.outcomes.c_str());
      } catch (const taskmap::Error& e) {
        std::printf("%-22s %-16s does not load: %s\n", label.c_str(), stem(mesh).c_str(), e.what());
      }
      std::fflush(stdout);
    }
  }
  return 0;
}
