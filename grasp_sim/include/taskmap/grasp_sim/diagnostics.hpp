#pragma once
/// @file diagnostics.hpp
/// Switches of the grasp simulator for tests and benchmarks: the baseline query paths the fast
/// ones are checked against, and per-phase timing. They are not options of a grasp simulation
/// (a map never records them, the CLI and Python do not offer them): the defaults are the
/// product; the other values exist to compare and to profile.

namespace taskmap {

/// Diagnostics switches of a GraspSimulator (its fourth constructor argument).
struct GraspSimDiagnostics {
  /// Link-versus-object queries: true = for mesh (hull) links, and for every link on meshes of
  /// 1000 faces or more, Bullet's tree walked with each link shape's face planes (box faces, hull
  /// faces, a 26-DOP otherwise), overlap proofs and a branch-and-bound nearest-triangle search, so
  /// that GJK/EPA runs only where the answer depends on it; and lean trial queries (only the
  /// penetrating hits for contacts, a yes/no for the squeeze limit, the nearest facing hit for
  /// coupled closing, shrinking thresholds for the approach): results bit for bit those of the
  /// baseline (contacts too with separating_axis_contacts false; except where Bullet's GJK would
  /// miss an overlap that a hull corner inside proves), much faster on fine meshes (docs/METHOD.md
  /// §2); false = the baseline, GJK on every triangle in the link shape's padded bounding box found
  /// through Bullet's tree, every exact hit computed.
  bool culled_queries = true;
  /// The final contacts of box and hull link shapes on meshes of 1000 faces or more (where
  /// culled queries treat boxes): true = depth and witness point per penetrated triangle from
  /// separating axes, docs/METHOD.md §2 "Contacts from separating axes": for a box the 13 axes
  /// of the pair (the exact penetration depth; the witness from the features of the axis, the
  /// centre of their overlap where they tie), for a hull its face of largest gap where the
  /// triangle's deepest corner lies that deep inside every face (then exact; elsewhere EPA);
  /// false = Bullet's EPA. EPA in double precision gives the same depths, and the same witness
  /// where the deepest features are unique; they differ where features tie (a face flat on a
  /// triangle: EPA returns some point of the overlap) and where Bullet's GJK calls an
  /// overlapping pair apart (which can give a finger its first contact). Closing and squeeze
  /// keep EPA: the pose and joints are the same either way, bit for bit. Needs culled_queries.
  bool separating_axis_contacts = true;
  /// The closing's self-collision test: true = each link pair's last separating axis is tried
  /// before GJK and proves most pairs apart (docs/METHOD.md §2), the same answers bit for bit;
  /// false = GJK/EPA on every pair whose bounding spheres are within the threshold (the
  /// previous path, kept to compare).
  bool self_collision_axes = true;
  /// Self-collision pairs: true = a pair whose relative pose one actuated joint alone changes
  /// (the links of a mimic-coupled gripper) and that GJK samples, spaced by a bound on the
  /// links' speed, prove farther apart than the contact tolerance over that joint's whole range
  /// is not tested (docs/METHOD.md §2, "Self-collision pairs proven apart"): its test would
  /// answer +inf at every pose, so the trials are the same bit for bit; false = every pair
  /// tested. Needs culled_queries.
  bool self_pair_proofs = true;
  /// Measure wall time per phase into GraspResult::stats (costs a few clock reads per trial).
  bool profile = false;
};

}  // namespace taskmap
