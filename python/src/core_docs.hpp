#pragma once
/// @file core_docs.hpp
/// Docstrings of taskmap._core (core_module.cpp, map_arrays.cpp, trajectory_bindings.cpp): the
/// run-time queries. Google style (Sphinx napoleon renders them; `tools/dev.sh docs` fails on
/// broken markup): what the call does, Args with units and frames, Returns, Raises, Example.
/// Poses are [x, y, z, qw, qx, qy, qz] (metres, unit quaternion) of the palm in the object
/// frame; gradients are 6-vectors (linear, angular) in the object frame.

namespace taskmap::pydoc {

inline constexpr const char* kTaskMap =
    R"doc(A loaded, indexed task map: the run-time queries of an optimizer.

Read-only after loading; every query is safe from many threads. Poses are
``[x, y, z, qw, qx, qy, qz]`` (metres, unit quaternion, q and -q alike) of the palm frame in
the object frame; gradients are 6-vectors (linear, angular) in the object frame. Obtain one
with :func:`taskmap.load`, :meth:`TaskMap.load` or :meth:`TaskMap.from_arrays`;
:func:`taskmap.build` returns the map it wrote.

Example:
    >>> m = taskmap.load("basket.h5")
    >>> len(m), m.num_clusters
)doc";

inline constexpr const char* kLoad = R"doc(Reads a task map file and indexes it for queries.

The file's seal (its SHA-256) is verified before HDF5 parses anything, so a damaged map, or one
edited with another HDF5 tool, is refused (re-seal it on purpose with :func:`taskmap.seal`).

Args:
    path (str): the map file (.h5), as written by ``taskmap build`` or :func:`taskmap.build`.
    **options: query options: ``index``, ``trees``, ``checks``, ``linear_weight`` (1/m^2),
        ``angular_weight`` (1/rad^2), ``position_sigma`` (m), ``rotation_sigma`` (rad),
        ``bandwidth_factor``, ``quality_mode`` (``"truncated"`` or ``"exact"``),
        ``quality_tolerance``, ``sample_weight`` (``"auto"``, ``"epsilon"``,
        ``"hold_margin"``), ``threads``; see :class:`TaskMap`.

Returns:
    TaskMap: the loaded map.

Raises:
    taskmap.Error: the file is missing, damaged, not a task map, or an option is out of range
        or unknown (naming the file or option).

Example:
    >>> m = taskmap.load("basket.h5", quality_mode="exact")
    >>> m.evaluate(m.pose(0))["nearest"]
    0
)doc";

inline constexpr const char* kFromArrays =
    R"doc(Builds a map in memory from poses and qualities (no file, no contacts).

Args:
    poses (numpy.ndarray): N x 7 palm poses in the object frame (metres, quaternions are
        normalised).
    epsilon (list of float): N qualities, the weights of the quality criterion (> 0: force
        closure).
    labels (list of int, optional): N cluster labels 0..K-1 without gaps, -1 for outliers;
        None leaves the map unclustered.
    rotation_scale (float): rho of the pose metric, metres per radian (default 0.1).
    **options: query options as for :func:`taskmap.load`.

Returns:
    TaskMap: the map; :meth:`TaskMap.save` writes it.

Raises:
    taskmap.Error: a label below -1, a cluster without grasps, or a wrong number of labels.

Example:
    >>> import numpy as np
    >>> m = taskmap.TaskMap.from_arrays(np.array([[0, 0, 0.1, 1, 0, 0, 0]]), [0.1])
)doc";

inline constexpr const char* kSave =
    R"doc(Writes the map to a file (sealed HDF5, atomically: a temporary file renamed).

Args:
    path (str): the file to write.

Returns:
    None

Raises:
    taskmap.Error: the file cannot be written.

Example:
    >>> m.save("copy.h5")
)doc";

inline constexpr const char* kPose = R"doc(The stored pose of grasp ``i``.

Args:
    i (int): grasp index, 0 <= i < len(map).

Returns:
    numpy.ndarray: ``[x, y, z, qw, qx, qy, qz]``, palm in the object frame (metres).

Raises:
    taskmap.Error: ``i`` out of range.

Example:
    >>> m.pose(0)
)doc";

inline constexpr const char* kNearest = R"doc(The grasp nearest to a pose in the pose metric.

The pose distance is ``d^2 = |dp|^2 + rho^2 (2 sin(theta/2))^2`` (metres; rho the map's rotation
scale); ties go to the smaller index. Exact unless the map was loaded with
``index="randomized"``.

Args:
    pose (numpy.ndarray): 7-vector, palm in the object frame (metres; quaternion qw qx qy qz).
    cluster (int, optional): search this cluster's grasps only.

Returns:
    tuple: ``(index, distance)``, distance in metres.

Raises:
    taskmap.Error: an unknown or empty cluster.

Example:
    >>> i, d = m.nearest(m.pose(3))
    >>> (i, d)
    (3, 0.0)
)doc";

inline constexpr const char* kKnn =
    R"doc(The ``k`` grasps nearest to a pose, nearest first (pose metric, metres).

Args:
    pose (numpy.ndarray): 7-vector, palm in the object frame (metres; quaternion qw qx qy qz).
    k (int): how many, >= 1 (fewer when the map or cluster has fewer).
    cluster (int, optional): search this cluster's grasps only.

Returns:
    tuple: ``(indices, distances)``, two numpy arrays.

Raises:
    taskmap.Error: ``k`` < 1, or an unknown or empty cluster.

Example:
    >>> idx, dist = m.knn(m.pose(0), 5)
)doc";

inline constexpr const char* kRadius =
    R"doc(Every grasp within a pose distance of a pose, nearest first.

Args:
    pose (numpy.ndarray): 7-vector, palm in the object frame (metres; quaternion qw qx qy qz).
    r (float): radius in the pose metric, metres, >= 0.
    cluster (int, optional): search this cluster's grasps only.

Returns:
    tuple: ``(indices, distances)``, two numpy arrays.

Raises:
    taskmap.Error: a negative or non-finite ``r``, or an unknown cluster.

Example:
    >>> idx, dist = m.radius(m.pose(0), 0.05)
)doc";

inline constexpr const char* kProximity =
    R"doc(The proximity criterion against the nearest grasp (paper eq. 1.18-1.19).

``g_p = w_p |dp|^2 + w_r |log(R_map^T R)|^2``, with (dp, log(R_map^T R)) the difference to the
nearest grasp; its gradient is in the object frame.

Args:
    pose (numpy.ndarray): 7-vector, palm in the object frame (metres; quaternion qw qx qy qz).
    cluster (int, optional): against this cluster's grasps only.

Returns:
    dict: ``value`` (float), ``gradient`` (6-vector: linear 1/m, angular 1/rad, object frame),
    ``nearest`` (index), ``distance`` (pose distance, m), ``difference`` (6-vector: dp in m,
    rotation vector in rad).

Raises:
    taskmap.Error: an unknown or empty cluster.

Example:
    >>> m.proximity(m.pose(0))["value"]
    0.0
)doc";

inline constexpr const char* kQuality =
    R"doc(The quality criterion: a mixture of Gaussians around the grasps (paper eq. 1.20-1.21).

g_q = -sum w_i f_i / sum w_i, f_i a normalised Gaussian in the pose embedding with widths
``position_sigma`` (m) and ``rotation_sigma`` (rad), w_i the sample weights (epsilon, or
epsilon x hold margin for a map with physics labels). The gradient is analytic, object frame.

Args:
    pose (numpy.ndarray): 7-vector, palm in the object frame (metres; quaternion qw qx qy qz).
    cluster (int, optional): the mixture of this cluster's grasps only.
    mode (str, optional): ``"exact"`` sums every grasp; ``"truncated"`` the grasps within
        ``cutoff_radius`` and bounds the rest; default the map's ``quality_mode``.

Returns:
    dict: ``value``, ``gradient`` (6-vector, object frame), ``value_bound`` and
    ``gradient_bound`` (what truncation may have left out; 0 in exact mode), ``terms`` (grasps
    summed).

Raises:
    taskmap.Error: an unknown mode or cluster.

Example:
    >>> q = m.quality(m.pose(0), mode="exact")
    >>> q["value"] < 0
    True
)doc";

inline constexpr const char* kEvaluate =
    R"doc(Proximity and quality with their gradients, from one index search: the once-per-iteration call.

Args:
    pose (numpy.ndarray): 7-vector, palm in the object frame (metres; quaternion qw qx qy qz).
    cluster (int, optional): against this cluster's grasps only.

Returns:
    dict: ``cost`` (proximity + quality), ``gradient`` (6-vector, object frame),
    ``proximity``, ``proximity_gradient``, ``quality``, ``quality_gradient``,
    ``quality_bound``, ``nearest`` (index) and ``nearest_distance`` (m).

Raises:
    taskmap.Error: an unknown or empty cluster.

Example:
    >>> e = m.evaluate(m.pose(0))
    >>> e["nearest"], e["nearest_distance"]
    (0, 0.0)
)doc";

inline constexpr const char* kSession =
    R"doc(A cache for one optimizer run: :meth:`Session.evaluate` returns what :meth:`evaluate` returns.

It keeps the grasps within ``cutoff_radius + margin`` of the last searched pose and answers
from them while the iterates stay within ``margin``; the nearest grasp is taken from the cache
only when the triangle inequality proves it exact. Not thread-safe: one session per thread.
The session keeps the map alive.

Args:
    margin (float, optional): metres in the pose metric; default a quarter of
        ``cutoff_radius``.
    cluster (int, optional): evaluate against this cluster only.

Returns:
    Session: the cache.

Raises:
    taskmap.Error: a negative margin or an unknown cluster.

Example:
    >>> s = m.session()
    >>> s.evaluate(m.pose(0))["nearest"]
    0
)doc";

inline constexpr const char* kEvaluateBatch =
    R"doc(:meth:`evaluate` for many poses, on the map's ``threads``.

Args:
    poses (numpy.ndarray): N x 7 palm poses in the object frame (metres; quaternions qw qx qy qz).
    cluster (int, optional): against this cluster's grasps only.

Returns:
    dict: ``proximity`` (N), ``proximity_gradient`` (N x 6), ``quality`` (N),
    ``quality_gradient`` (N x 6), ``quality_bound`` (N), ``nearest`` (N) and
    ``nearest_distance`` (N, m); row i exactly as ``evaluate(poses[i])``.

Raises:
    taskmap.Error: an unknown or empty cluster.

Example:
    >>> b = m.evaluate_batch(m.poses[:10])
)doc";

inline constexpr const char* kNearestBatch =
    R"doc(:meth:`nearest` for many poses, on the map's ``threads``.

Args:
    poses (numpy.ndarray): N x 7 palm poses in the object frame (metres; quaternions qw qx qy qz).
    cluster (int, optional): search this cluster's grasps only.

Returns:
    tuple: ``(indices, distances)``, two numpy arrays of N (distances in metres).

Raises:
    taskmap.Error: an unknown or empty cluster.

Example:
    >>> idx, dist = m.nearest_batch(m.poses)
    >>> float(dist.max())
    0.0
)doc";

inline constexpr const char* kRankClusters =
    R"doc(Ranks the clusters for a planner's start (paper §1.6.2): your IK, your comfort cost.

Each cluster's representative grasp is placed in the world with the object's pose and handed
to ``ik``; the reachable clusters come first, cheapest ``comfort`` first.

Args:
    object_world (numpy.ndarray): 7-vector, the object's pose in the world (metres).
    ik (callable): ``ik(target_world)`` takes a 7-vector palm pose in the world and returns the
        joint vector reaching it, or None when it cannot.
    comfort (callable): ``comfort(q)`` returns the cost of a posture (lower is better), e.g.
        :func:`taskmap.joint_limit_cost`.
    member_tries (int): when no representative is reachable, try up to this many other members
        of each cluster (farthest from the representative first), then as many outliers
        (cluster -1); 0 (default): representatives only.

Returns:
    list: one dict per cluster, best first: ``cluster``, ``representative``, ``target`` (the
    grasp tried last), ``tried`` (IK calls), ``target_object`` and ``target_world`` (7-vectors),
    ``reachable``, ``q``, ``comfort``, ``message``.

Raises:
    Exception: whatever ``ik`` or ``comfort`` raise.

Example:
    >>> ranks = m.rank_clusters(np.array([0.5, 0, 0, 1, 0, 0, 0]), lambda t: t[:3],
    ...                         lambda q: float(q @ q))
)doc";

inline constexpr const char* kContacts = R"doc(Grasp ``i``'s recorded contacts.

Args:
    i (int): grasp index.

Returns:
    dict: ``points`` (K x 3, metres, object frame), ``normals`` (K x 3, unit, out of the
    object), ``depths`` (K, metres of penetration), ``links`` (K indices into
    :attr:`link_names`) and ``link_names`` (K names, None where unknown).

Raises:
    IndexError: ``i`` out of range.
    taskmap.Error: the map stores no contacts (an imported map).

Example:
    >>> c = m.contacts(0)
    >>> c["points"].shape[1]
    3
)doc";

inline constexpr const char* kSessionClass =
    R"doc(Cached evaluation for one optimizer run (:meth:`TaskMap.session`); not thread-safe.

Example:
    >>> s = m.session(margin=0.01)
    >>> s.evaluate(m.pose(0))["nearest"]
    0
)doc";

inline constexpr const char* kError = R"doc(The error of every taskmap call: bad input, named.

A :class:`ValueError`. Its message names the file, option or argument at fault and, for a
misspelt hand or object name, the closest names ("did you mean 'basket'?").

Example:
    >>> try:
    ...     taskmap.load("no_such_map.h5")
    ... except taskmap.Error as e:
    ...     print(e)
)doc";

inline constexpr const char* kSessionEvaluate =
    R"doc(What :meth:`TaskMap.evaluate` returns for ``pose``, from the cache when it can.

Args:
    pose (numpy.ndarray): 7-vector, palm in the object frame (metres; quaternion qw qx qy qz).

Returns:
    dict: the same keys and values as :meth:`TaskMap.evaluate` (sums up to rounding order).

Raises:
    taskmap.Error: an empty cluster.

Example:
    >>> s = m.session()
    >>> s.evaluate(m.pose(0))["cost"] == m.evaluate(m.pose(0))["cost"]
    True
)doc";

inline constexpr const char* kSessionReset = R"doc(Drops the cache and zeroes :attr:`stats`.

Raises nothing.

Returns:
    None

Example:
    >>> s.reset()
)doc";

inline constexpr const char* kSeal =
    R"doc(Re-seals a map on purpose after editing it with h5py (or a map without a seal).

Validates the file as a task map, then rewrites it atomically with a fresh SHA-256 seal in its
first 512 bytes. HDF5 parses the unverified file in this process; ``taskmap seal FILE``
isolates that in a child process with memory and CPU limits.

Args:
    path (str): the map file.

Returns:
    None

Raises:
    taskmap.Error: the file is not a valid task map (naming what is wrong) or has another user
        block.

Example:
    >>> taskmap.seal("edited.h5")
)doc";

inline constexpr const char* kDataDir =
    R"doc(The bundled data directory: hands/, objects/, maps/, robots/, regression/.

The first of ``$TASKMAP_DATA_DIR``, ``share/taskmap`` beside the running executable's prefix,
and ``share/taskmap`` beside libtaskmap_core (``<venv>/share/taskmap`` after ``pip install``).

Returns:
    str: the directory.

Raises:
    taskmap.Error: none exists (saying how to set ``TASKMAP_DATA_DIR``).

Example:
    >>> import os
    >>> os.path.exists(os.path.join(taskmap.data_dir(), "maps", "basket_humanoid.h5"))
    True
)doc";

inline constexpr const char* kHandInObject =
    R"doc(The palm pose in the object frame from world poses: T_wo^-1 T_wh.

Args:
    hand_world (numpy.ndarray): 7-vector, palm in the world (metres).
    object_world (numpy.ndarray): 7-vector, object in the world (metres).

Returns:
    numpy.ndarray: 7-vector, palm in the object frame (what the queries take).

Raises:
    TypeError: a pose that is not a 7-vector of numbers.
    taskmap.Error: a non-finite value or a zero quaternion.

Example:
    >>> taskmap.hand_in_object(np.array([0.5, 0, 0.1, 1, 0, 0, 0]),
    ...                        np.array([0.5, 0, 0, 1, 0, 0, 0]))
)doc";

inline constexpr const char* kHandGradientToWorld =
    R"doc(An object-frame gradient as a gradient of the palm's world pose: (R_wo g_lin, R_wo g_ang).

Args:
    gradient (numpy.ndarray): 6-vector (linear: per metre, angular: per radian), object frame
        (``Evaluation``'s ``gradient``).
    object_world (numpy.ndarray): 7-vector, object in the world frame (metres; quaternion qw qx qy qz).

Returns:
    numpy.ndarray: 6-vector in world coordinates, for the perturbation a geometric Jacobian
    gives (linear velocity of the palm origin, angular velocity).

Raises:
    TypeError: a gradient that is not a 6-vector or a pose that is not a 7-vector.
    taskmap.Error: a pose with a non-finite value or a zero quaternion.

Example:
    >>> g = taskmap.hand_gradient_to_world(e["gradient"], object_world)
)doc";

inline constexpr const char* kObjectGradientToWorld =
    R"doc(An object-frame gradient as a gradient of the object's world pose, the hand fixed in the world.

(-R_wo g_lin, (R_wo g_lin) x (p_wh - p_wo) - R_wo g_ang).

Args:
    gradient (numpy.ndarray): 6-vector (linear: per metre, angular: per radian), object frame
        (``Evaluation``'s ``gradient``).
    hand_world (numpy.ndarray): 7-vector, palm in the world frame (metres; quaternion qw qx qy qz).
    object_world (numpy.ndarray): 7-vector, object in the world frame (metres; quaternion qw qx qy qz).

Returns:
    numpy.ndarray: 6-vector in world coordinates.

Raises:
    TypeError: a gradient that is not a 6-vector or a pose that is not a 7-vector.
    taskmap.Error: a pose with a non-finite value or a zero quaternion.

Example:
    >>> g = taskmap.object_gradient_to_world(e["gradient"], hand_world, object_world)
)doc";

inline constexpr const char* kJointGradient =
    R"doc(The joint-space gradient of an object-frame criterion (paper eq. 1.22).

J_hand^T g_hand_world + J_object^T g_object_world, the Jacobians geometric (rows: linear,
angular; world coordinates), for a hand and, optionally, an object that move with the joints.

Args:
    gradient (numpy.ndarray): 6-vector (linear: per metre, angular: per radian), object frame
        (``Evaluation``'s ``gradient``).
    hand_world (numpy.ndarray): 7-vector, palm in the world frame (metres; quaternion qw qx qy qz).
    object_world (numpy.ndarray): 7-vector, object in the world frame (metres; quaternion qw qx qy qz).
    hand_jacobian (numpy.ndarray): 6 x n geometric Jacobian of the palm in the world frame
        (rows: linear in metres, angular in radians, per unit of each joint).
    object_jacobian (numpy.ndarray, optional): 6 x n geometric Jacobian of the object in the
        world frame (rows: linear in metres, angular in radians, per unit of each joint; None:
        the object is fixed).

Returns:
    numpy.ndarray: n-vector, d(criterion)/dq.

Raises:
    TypeError: a gradient that is not a 6-vector or a pose that is not a 7-vector.
    taskmap.Error: a Jacobian without 6 rows, column counts that differ, or a pose with a
        non-finite value or a zero quaternion.

Example:
    >>> dq = taskmap.joint_gradient(e["gradient"], hand_world, object_world, J)
)doc";

inline constexpr const char* kPoseDistance =
    R"doc(The pose distance of the maps: ``sqrt(|dp|^2 + rho^2 (2 sin(theta/2))^2)``.

Args:
    a (numpy.ndarray): 7-vector pose (metres; quaternion qw qx qy qz).
    b (numpy.ndarray): 7-vector pose in the same frame as ``a``.
    rho (float): metres per radian (default 0.1; a map's is ``m.rotation_scale``).

Returns:
    float: metres.

Raises:
    TypeError: a pose that is not a 7-vector of numbers.
    taskmap.Error: a non-finite value or a zero quaternion.

Example:
    >>> taskmap.pose_distance(np.array([0, 0, 0, 1, 0, 0, 0]), np.array([3, 0, 4, 1, 0, 0, 0]))
    5.0
)doc";

inline constexpr const char* kReadTrajectory =
    R"doc(Reads a trajectory file (``taskmap reach --map ... -o``) after checking its seal.

Unlike h5py, which would parse unverified bytes. Layout in mapstore/TRAJECTORY.md.

Args:
    path (str): the trajectory file (.h5).

Returns:
    dict: ``generator``, ``created_utc``, ``robot``, ``hand``, ``dt`` (s), ``joint_names``,
    ``joints`` (S x D, rad), ``palm_world`` and ``palm_object`` (S x 7), ``object_name``,
    ``object_pose`` (7), ``object_vertices``, ``object_faces``, ``map_path``, ``map_sha256``,
    ``start_cluster``, ``cluster``, ``grasp_index``, ``quality_peak`` (q*: the quality columns
    are w_map,q g_q / q*; 1 in older files), ``map_hand``, ``map_hand_sha256``,
    ``map_hand_path``, ``grasp_joint_names``, ``grasp_joints`` (J, rad; empty in files written
    before they were recorded), ``cost_terms``, ``cost_history``
    ((I+1) x terms), ``proximity_over_movement`` and ``quality_over_movement`` (S),
    ``body_names``, ``body_parents``, ``body_roles``, ``body_poses`` (S x B x 7), ``shapes``
    (``body``, ``type``, ``params`` P x 15).

Raises:
    taskmap.Error: the file is missing, damaged or not a trajectory file.

Example:
    >>> t = taskmap.read_trajectory("reach.h5")
    >>> t["joints"].shape
)doc";

}  // namespace taskmap::pydoc
