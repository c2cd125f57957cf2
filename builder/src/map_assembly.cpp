// Assembling a map from blocks of trial outcomes in index order (the stop rule of buildMap),
// shared by buildMap and taskmap-mpi.
#include <cassert>
#include <string>
#include <vector>

#include "build_diagnosis.hpp"
#include "params_json.hpp"
#include "taskmap/builder/trial_block.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/validate/validate_map.hpp"
#include "trial_pool.hpp"

#ifndef TASKMAP_VERSION
#define TASKMAP_VERSION "unknown"
#endif

namespace taskmap {
namespace {

// Outcome names: the simulator's statuses, with ok split by force closure.
constexpr const char* kForceClosure = "force_closure";
constexpr const char* kNotForceClosure = "not_force_closure";
constexpr const char* kUnbalanced = "unbalanced";
constexpr const char* kPushed = "pushed";
constexpr const char* kWeakSqueeze = "weak_squeeze";
constexpr const char* kNotHolding = "not_holding";

std::string outcomeName(const TrialOutcome& t) {
  if (t.status != GraspStatus::kOk) return toString(t.status);
  if (t.weak_squeeze) return kWeakSqueeze;
  if (t.unbalanced) return kUnbalanced;
  if (t.pushed) return kPushed;
  if (t.not_holding) return kNotHolding;
  return t.force_closure ? kForceClosure : kNotForceClosure;
}

// Appends a stored grasp as the next row.
void appendGrasp(const TrialOutcome& t, std::size_t row, MapGrasps& g) {
  const TrialGrasp& r = *t.grasp;
  const auto i = static_cast<Eigen::Index>(row);
  g.pose.row(i) = r.pose.toVector7().transpose();
  assert(r.joints.size() == g.joints.cols());
  g.joints.row(i) = r.joints.transpose();
  g.force_closure.push_back(t.force_closure ? 1 : 0);
  g.epsilon.push_back(t.epsilon);
  g.volume.push_back(t.volume);
  g.contact_offsets.push_back(g.contact_offsets.back() +
                              static_cast<std::int64_t>(r.contacts.size()));
}

// ---- the steps of assembleMap

// ---- the steps of buildMap

// The map's descriptive groups: provenance, object, hand, sampling parameters, quality model.
void describeMap(const ObjectModel& object, const HandModel& hand, const BuildOptions& options,
                 TaskMapData& map) {
  map.generator = std::string("taskmap ") + TASKMAP_VERSION;
  map.created_utc = mapCreationTime();  // SOURCE_DATE_EPOCH or "": reproducible bytes
  map.object = mapObjectOf(object);
  map.hand.name = hand.name();
  map.hand.urdf_sha256 = hand.urdfSha256();
  map.hand.joint_names = hand.jointNames();
  for (const HandLink& l : hand.links()) map.hand.link_names.push_back(l.name);
  map.sampling.sampler = toString(detail::samplerKindFor(options, hand));
  map.sampling.seed = options.seed;
  map.sampling.params_json = detail::paramsJson(options, hand);
  map.quality.friction = options.quality.friction;
  map.quality.cone_edges = options.quality.cone_edges;
  map.quality.contact_model = toString(options.quality.contact_model);
}

// What the completed prefix of blocks holds up to the valid_target-th force-closure grasp.
struct Prefix {
  std::uint64_t trials = 0, valid = 0;
  std::vector<const TrialOutcome*> stored;
  std::size_t contacts = 0;
};

// Walks the completed blocks in index order (the stop rule), counting outcomes into map.
Prefix takePrefix(const std::vector<TrialBlock>& blocks, std::uint64_t valid_target,
                  TaskMapData& map) {
  Prefix p;
  for (std::size_t b = 0; b < blocks.size() && p.valid < valid_target; ++b) {
    for (const TrialOutcome& t : blocks[b].trials) {
      ++p.trials;
      ++map.sampling.outcomes[outcomeName(t)];
      if (t.grasp) {
        p.stored.push_back(&t);
        p.contacts += t.grasp->contacts.size();
      }
      if (t.force_closure && ++p.valid == valid_target) break;
    }
  }
  map.sampling.trials = p.trials;
  return p;
}

// The grasp rows (poses, joints, qualities, contacts) of the stored trials, in trial order.
void fillGrasps(const Prefix& prefix, double rho, TaskMapData& map) {
  MapGrasps& g = map.grasps;
  const auto n = static_cast<Eigen::Index>(prefix.stored.size());
  const auto joints = static_cast<Eigen::Index>(map.hand.joint_names.size());
  g.rotation_scale = rho;
  g.contacts_available = true;
  g.pose.resize(n, 7);
  g.joints.resize(n, joints);
  g.contact_offsets.assign(1, 0);
  g.contact_points.resize(static_cast<Eigen::Index>(prefix.contacts), 3);
  g.contact_normals.resize(static_cast<Eigen::Index>(prefix.contacts), 3);
  std::size_t c = 0;
  for (std::size_t i = 0; i < prefix.stored.size(); ++i) {
    appendGrasp(*prefix.stored[i], i, g);
    for (const Contact& k : prefix.stored[i]->grasp->contacts) {
      g.contact_points.row(static_cast<Eigen::Index>(c)) = k.point.transpose();
      g.contact_normals.row(static_cast<Eigen::Index>(c)) = k.normal.normalized().transpose();
      g.contact_depths.push_back(k.depth);
      g.contact_links.push_back(k.link);
      ++c;
    }
  }
}

// The hold labels of the stored grasps the build's hold test ran on (BuildOptions::hold_test):
// the protocol's for kNominal, the robust label's too for kRobust (its variants: every
// tested grasp ran the same list, the second decomposition's included or not).
void labelGrasps(const Prefix& prefix, const HandModel& hand, const BuildOptions& options,
                 TaskMapData& map) {
  if (options.hold_test == BuildHoldTest::kOff) return;
  std::vector<const RobustHoldResult*> results;
  std::size_t variants = 0;
  for (const TrialOutcome* t : prefix.stored) {
    results.push_back(t->grasp->hold ? &*t->grasp->hold : nullptr);
    if (t->grasp->hold) variants = t->grasp->hold->variant_held.size();
  }
  const HoldTestOptions& protocol = options.hold_test_options.hold;
  if (options.hold_test == BuildHoldTest::kNominal || variants == 0) {
    map.validation = holdLabels(results, protocol);
  } else {
    const RobustHoldOptions& ro = options.hold_test_options;
    const bool decomposition = robustVariants(ro, true).size() == variants;
    map.validation = holdLabels(results, protocol, &ro, robustVariants(ro, decomposition));
  }
  recordHandDynamics(handDynamicsJson(hand, protocol), &*map.validation);
}

// Clusters the stored grasps (paper 1.6.1) in the hand's pose metric.
void clusterMap(const ClusteringOptions& options, double rho, TaskMapData& map) {
  const MapGrasps& g = map.grasps;
  std::vector<Pose> poses;
  poses.reserve(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) poses.push_back(g.poseAt(i));
  ClusteringOptions co = options;
  co.rotation_scale = rho;
  map.clustering = clusterGrasps(poses, g.epsilon, co);
}

// What valid_target counts, for messages.
std::string validName(const BuildOptions& options) {
  switch (options.hold_test) {
    case BuildHoldTest::kRobust:
      return "grasps that hold robustly";
    case BuildHoldTest::kNominal:
      return "grasps that hold";
    case BuildHoldTest::kOff:
      break;
  }
  return "force-closure grasps";
}

// The build's status and its one-line message.
void setStatus(bool interrupted, const Prefix& p, const BuildOptions& options, BuildResult& r) {
  if (interrupted) {
    r.status = BuildStatus::kInterrupted;
    r.message = "interrupted after " + std::to_string(p.trials) + " trials with " +
                std::to_string(p.valid) + " " + validName(options);
  } else if (p.stored.empty()) {
    r.status = BuildStatus::kNoGrasps;  // message: noGraspMessage (needs object and hand)
  } else if (p.valid < options.valid_target) {
    r.status = BuildStatus::kTrialBudgetExhausted;
    r.message = "trial budget of " + std::to_string(options.max_trials) + " spent: found " +
                std::to_string(p.valid) + " of " + std::to_string(options.valid_target) + " " +
                validName(options);
  } else {
    r.status = BuildStatus::kComplete;
    r.message = "found " + std::to_string(p.valid) + " " + validName(options) + " in " +
                std::to_string(p.trials) + " trials";
  }
}

// Throws unless the blocks are consecutive from trial 0.
void checkConsecutive(const std::vector<TrialBlock>& blocks) {
  std::uint64_t next = 0;
  for (const TrialBlock& b : blocks) {
    if (b.first != next)
      throw Error("assembleMap: blocks must cover the trials from 0 in order; expected trial " +
                  std::to_string(next) + ", got a block starting at " + std::to_string(b.first));
    next = b.end();
  }
}

}  // namespace

MapObject mapObjectOf(const ObjectModel& object) {
  MapObject o;
  const MassProperties& mp = object.massProperties();
  o.name = object.name();
  o.source_sha256 = object.sourceSha256();
  o.scale = object.scale();
  o.volume = mp.volume;
  o.center_of_mass = mp.center_of_mass;
  o.torque_scale = mp.torque_scale;
  const TriangleMesh& mesh = object.mesh();
  o.vertices.resize(static_cast<Eigen::Index>(mesh.vertices.size()), 3);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    o.vertices.row(static_cast<Eigen::Index>(i)) = mesh.vertices[i].transpose();
  o.faces.resize(static_cast<Eigen::Index>(mesh.faces.size()), 3);
  for (std::size_t i = 0; i < mesh.faces.size(); ++i)
    o.faces.row(static_cast<Eigen::Index>(i)) = mesh.faces[i].cast<std::int64_t>().transpose();
  return o;
}

BuildResult assembleMap(const ObjectModel& object, const HandModel& hand,
                        const BuildOptions& options, const std::vector<TrialBlock>& blocks,
                        bool interrupted, const BuildTiming& timing) {
  checkConsecutive(blocks);
  BuildResult result;
  result.timing = timing;
  TaskMapData& map = result.map;
  describeMap(object, hand, options, map);
  const Prefix prefix = takePrefix(blocks, options.valid_target, map);
  const double rho = hand.rotationScale() > 0.0 ? hand.rotationScale() : kDefaultRotationScale;
  fillGrasps(prefix, rho, map);
  labelGrasps(prefix, hand, options, map);
  if (options.cluster && prefix.stored.size() >= 2 && !interrupted) {
    const auto t_cluster = detail::Clock::now();
    clusterMap(options.clustering, rho, map);
    result.timing.clustering_seconds = detail::secondsSince(t_cluster);
  }
  setStatus(interrupted, prefix, options, result);
  if (result.status == BuildStatus::kNoGrasps)
    result.message = detail::noGraspMessage(map.sampling.outcomes, prefix.trials, object, hand);
  return result;
}

}  // namespace taskmap
