#pragma once
// Private to grasp_sim: what every trial of one GraspSimulator reads (built once, shared
// read-only by all threads): the hand, the options, the collision scene and the derived
// per-link and per-joint tables.

#include <memory>
#include <utility>
#include <vector>

#include "collision_scene.hpp"
#include "taskmap/core/triangle_mesh.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// The simulator's fixed data (docs/METHOD.md §2).
struct SimModel {
  HandModel hand;                         ///< the hand simulated
  GraspSimOptions opt;                    ///< validated options
  GraspSimDiagnostics diag;               ///< baseline paths and profiling
  std::unique_ptr<CollisionScene> scene;  ///< object BVH and link shapes
  /// diag.culled_queries: queries ask only what the trial uses (penetrating hits for contacts,
  /// a yes/no for the squeeze limit); false runs the baseline's full exact queries.
  bool lean_queries = true;
  double squeeze = 0.0;           ///< squeeze distance in force, metres
  double retract_step = 0.0;      ///< coarse retraction step, metres
  std::vector<int> shaped;        ///< links with collision shapes
  std::vector<double> thickness;  ///< per link, metres; +inf without shapes
  std::vector<double> radius;     ///< per link, its enclosing sphere's (scene->linkRadius)
  std::vector<int> closing_of;    ///< actuated joint -> index in hand.closing(), or -1
  std::vector<std::pair<int, int>> self_pairs;  ///< link pairs checked for self-collision
  std::vector<std::vector<int>> partners;       ///< per link: its self-collision partners
  /// Per link and partner (partners' layout): the link's index in its partner's list.
  std::vector<std::vector<int>> partner_slot;
  GraspMode grasp_mode = GraspMode::kPalm;  ///< palm or fingertip grasps in force
  double standoff = 0.0;                    ///< fingertip standoff in force, metres
  /// Coupled mechanisms that centre (closing indices per group): a closing joint, or a sidecar
  /// "coupled" group, whose links lie on two or more fingers; empty unless opt.centre_coupled.
  std::vector<std::vector<int>> groups;
  std::vector<int> group_of;                   ///< closing index -> index in groups, or -1
  std::vector<std::vector<char>> group_moves;  ///< per group, per link: moved by the group

  /// Validates `o`, builds the scene and the tables. Throws Error on bad input.
  SimModel(const TriangleMesh& mesh, const HandModel& h, const GraspSimOptions& o,
           const GraspSimDiagnostics& d);

 private:
  void findCoupledGroups();
};

/// Drops from m->self_pairs every pair whose relative pose one actuated joint alone changes and
/// that stays farther apart than the contact tolerance over that joint's whole range (proven by
/// GJK samples and a bound on the links' speed; self_pair_proof.cpp): its self-collision test
/// answers +inf at every pose a trial can reach, so no result changes.
void dropPairsProvenApart(SimModel* m);

}  // namespace taskmap
