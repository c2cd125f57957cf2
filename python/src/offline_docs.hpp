#pragma once
/// @file offline_docs.hpp
/// Docstrings of taskmap._offline (builder, reaching, validate, inspect, picture and export
/// bindings): one call per command of the CLI. Google style, as core_docs.hpp: what the call
/// does, Args with units and frames, Returns, Raises, Example.

namespace taskmap::pydoc {

inline constexpr const char* kBuild =
    R"doc(Builds a task map as ``taskmap build`` does, writes it and returns it loaded.

The same options give the same map bytes as the command line, for any thread count. Each
trial samples a palm pose, simulates the grasp, scores force closure and, with the default
``hold_test="robust"``, tests the grasp in physics as it is found: ``valid`` counts grasps that
hold (docs/BUILDING.md). The build releases the GIL while the trials run.

Args:
    object (str): the object: a mesh file (any format assimp reads) or a bundled object's name
        (``"basket"``, ``"box"``, ``"bowl"``, ``"cylinder"``, ``"mug"``, ``"sphere"``). Its
        coordinates times ``scale`` are metres in the object frame.
    hand (str): a hand URDF or MJCF (with its ``<stem>.hand.json`` sidecar beside it) or a
        bundled hand's name (``"barrett"``, ``"panda"``, ``"humanoid"``).
    output (str): the map file to write (.h5; written atomically, never over an input).
    scale (float): file units to metres (default 1).
    no_repair (bool): refuse a mesh that needs repair.
    repair (str): ``"wrap"`` also closes an open surface by alpha wrapping.
    wrap_alpha (float): with ``repair="wrap"``, openings narrower than about this are sealed
        (metres; 0: bounding-box diagonal / 100).
    wrap_offset (float): with ``repair="wrap"``, the wrap's distance outside the surface
        (metres; 0: diagonal / 3000).
    force (bool): replace an existing output that is not a task map.
    progress (callable, optional): called about every 0.25 s with a dict ``trials_done``,
        ``valid_found``, ``valid_target``, ``max_trials``, ``elapsed_seconds``; an exception it
        raises stops the build and is raised here.
    **knobs: the build options of ``taskmap build``, named with ``_`` for ``-`` (listed below
        with their defaults).

Returns:
    TaskMap: the written map, loaded (:func:`taskmap.load`).

Raises:
    taskmap.Error: bad input (a missing file, an implausible object size, an option out of
        range), naming the file or option; also when the build stores no grasp (nothing
        written).
    TypeError: a keyword that is not a build option, or a value of the wrong type.
    KeyboardInterrupt: Ctrl-C; nothing is written.

Example:
    >>> m = taskmap.build(object="basket", hand="barrett", valid=10, seed=1, output="basket.h5")
    >>> len(m)
    10
)doc";

inline constexpr const char* kDataset =
    R"doc(Builds one task map per (object, hand) into a directory, as ``taskmap dataset`` does.

The maps are ``<mesh stem>__<hand>.h5`` with ``manifest.json`` beside them (rewritten after
every job). Each job's seed derives from ``seed`` and the contents of mesh and hand, so neither
the list order nor the number of processes changes a map. A re-run skips maps whose file and
parameters match the manifest; a mesh that does not load is recorded as ``failed``, not raised.

Args:
    objects (str): a text file naming one mesh a line (relative to the file; ``#`` comments),
        optionally followed by its scale (file units to metres).
    hands (list of str): hand URDFs or MJCFs, or bundled hand names.
    output (str): the directory (created when missing).
    scale (float): the scale of meshes the list gives none (file units to metres).
    force (bool): replace files in the directory that are not taskmap files.
    progress (callable, optional): called after each job with a dict ``done``, ``total``,
        ``elapsed_seconds`` and ``entry`` (the job's manifest entry).
    **knobs: the build options, as for :func:`taskmap.build` (listed below).

Returns:
    dict: ``jobs``, ``skipped``, ``failed``, ``dir`` and ``manifest`` (its path).

Raises:
    taskmap.Error: a bad list, hand or option, naming it.
    TypeError: a keyword that is not a build option.
    KeyboardInterrupt: Ctrl-C; the current map is not written, its entry stays ``pending``.

Example:
    >>> r = taskmap.dataset(objects="list.txt", hands=["panda"], output="maps", valid=10,
    ...                     hold_test="off")
    >>> r["failed"]
    0
)doc";

inline constexpr const char* kImportAcronym =
    R"doc(Turns an ACRONYM grasp file into a task map, as ``taskmap import`` does (the same bytes).

Poses come from ``grasps/transforms`` (the gripper's base frame, converted to the palm frame),
force closure from ``grasps/qualities/flex/object_in_gripper``, epsilon from taskmap's own
epsilon when the file has it (else the success flag); no contacts. The file is read in a child
process with memory and CPU limits.

Args:
    acronym (str): the ACRONYM file (.h5).
    object (str): the object's mesh file, or a bundled object's name.
    output (str): the map file to write.
    scale (float): file units to metres of the mesh (0: the file's ``object/scale``).
    successful_only (bool): keep only grasps with ``object_in_gripper`` = 1.
    no_cluster (bool): leave the map unclustered.
    linkage (str): ``"single"``, ``"average"`` or ``"complete"``.
    rotation_scale (float): rho of the pose metric, metres per radian.
    threshold (float, optional): cut distance, metres (default: the build's default cut).
    clusters (int, optional): cut into this many clusters.
    min_size_fraction (float): clusters below this share of the grasps are outliers.
    palm_offset (float, optional): the palm frame ``palm_offset`` metres along the base's z.
    hand (str): a hand whose URDF root is the base frame: its root-to-palm transform converts
        (default: ACRONYM's Franka gripper, 0.1034 m along z). A parallel-jaw gripper's jaws
        are closed from open at each pose to give the joint values, and the map records the
        hand, so that :func:`validate` tests the grasps (grasps whose jaws miss the object are
        dropped).
    timestamp (bool): store the current time.
    force (bool): replace an existing output that is not a task map.

Returns:
    TaskMap: the written map, loaded.

Raises:
    taskmap.Error: a missing or bad file, naming it; nothing is written.

Example:
    >>> m = taskmap.import_acronym(acronym="mug_grasps.h5", object="mug.obj", output="mug.h5")
)doc";

inline constexpr const char* kRecluster =
    R"doc(Re-clusters a map's grasps, as ``taskmap cluster MAP`` does.

Hierarchical clustering in the map's pose metric; the stored dendrogram is reused when the
linkage is unchanged. Writes the labels, cluster table and dendrogram into the map (atomically)
or into ``output``.

Args:
    map (str): the map file.
    threshold (float, optional): cut distance in the pose metric, metres.
    clusters (int, optional): cut into this many groups (not with ``threshold``).
    min_size (int, optional): smallest cluster kept (default 3 % of the grasps, at least 3);
        smaller groups are outliers (label -1).
    method (str, optional): ``"single"``, ``"average"`` or ``"complete"`` (default average,
        single beyond 20000 grasps).
    outlier_budget (float, optional): share of grasps the default cut may leave as outliers,
        in [0, 1] (default 0.1).
    output (str): write here instead (never an input).
    force (bool): replace an output that is not a task map.

Returns:
    TaskMap: the re-clustered map, loaded.

Raises:
    taskmap.Error: a missing map or a bad argument, naming it.

Example:
    >>> taskmap.recluster("basket.h5", clusters=4).num_clusters
    4
)doc";

inline constexpr const char* kRegress =
    R"doc(Runs the regression suite, as ``taskmap regress`` does.

Builds each reference case (fixed seed and trial budget) and compares its statistics (trials
per outcome, valid rate, epsilon quantiles, cluster sizes and representatives) with its golden
file, or rewrites the golden files.

Args:
    cases (str): the case list (JSON; default ``<data dir>/regression/cases.json``).
    golden (str): the folder of golden files (default ``<cases folder>/golden``).
    only (list of str): run these cases only.
    update (bool): rewrite the golden files instead of comparing.
    threads (int): worker threads (0: all cores; results do not depend on it).
    friction (float, optional): override the friction (to see the suite catch a change).

Returns:
    dict: ``cases`` (one dict per case: ``name``, ``object``, ``hand``, ``golden``, ``outcome``
    ``"compared"``/``"updated"``/``"no_golden"``, ``failures``, ``rows`` of ``statistic``,
    ``golden``, ``now``, ``pass``, and ``text`` as the CLI prints it), ``failures``,
    ``golden_dir``.

Raises:
    taskmap.Error: a bad case list, or no case matches ``only``.

Example:
    >>> taskmap.regress(only=["box_panda"])["failures"]
    0
)doc";

inline constexpr const char* kRobot =
    R"doc(A robot arm (URDF), optionally with a hand on its flange and a scene of fixed bodies.

Metres and radians; the world frame is the robot's root frame. Collision primitives are
capsules and sphere-swept rectangles (docs/REACHING.md).

Example:
    >>> d = taskmap.data_dir()
    >>> robot = taskmap.Robot.panda_with_humanoid_hand(d + "/robots", d + "/hands")
    >>> robot.dofs
    7
)doc";

inline constexpr const char* kRobotLoad =
    R"doc(A robot from a URDF (its capsules from ``<stem>.capsules.json`` when present).

Args:
    urdf (str): the robot's URDF (revolute, continuous, prismatic and fixed joints).

Returns:
    Robot: the arm, without a hand.

Raises:
    taskmap.Error: a missing file or an unsupported joint, naming it.

Example:
    >>> arm = taskmap.Robot.load(taskmap.data_dir() + "/robots/panda/panda.urdf")
)doc";

inline constexpr const char* kRobotPandaHumanoid =
    R"doc(The bundled Panda with the humanoid hand on its flange (the sidecar's mount).

Args:
    robots_dir (str): the folder holding ``panda/`` (``<data dir>/robots``).
    hands_dir (str): the folder holding ``humanoid/`` (``<data dir>/hands``).

Returns:
    Robot: the arm with the hand; its body ``palm`` is the palm frame.

Raises:
    taskmap.Error: a missing file.

Example:
    >>> d = taskmap.data_dir()
    >>> robot = taskmap.Robot.panda_with_humanoid_hand(d + "/robots", d + "/hands")
)doc";

inline constexpr const char* kRobotAddScene =
    R"doc(Adds a scene file's fixed bodies and names its object.

Args:
    path (str): a scene JSON (docs/REACHING.md, "Scenes"); ``""`` adds the default scene, a
        table and an upright cylinder at (0.5, 0.2, 0.1) m.

Returns:
    None

Raises:
    taskmap.Error: a missing or malformed file, naming it.

Example:
    >>> robot.add_scene("reaching/scenes/basket_reference.json")
    >>> robot.object
    'basket'
)doc";

inline constexpr const char* kRobotFk = R"doc(The world pose of every body at a joint configuration.

Args:
    q (numpy.ndarray): joint values (radians; metres for prismatic joints), ``dofs`` long.

Returns:
    list: 4 x 4 homogeneous matrices, in :attr:`body_names` order (metres).

Raises:
    taskmap.Error: ``q`` of the wrong length.

Example:
    >>> poses = robot.forward_kinematics(np.zeros(robot.dofs))
)doc";

inline constexpr const char* kRobotJacobian =
    R"doc(The geometric Jacobian of a body relative to another (paper eq. 1.4-1.5).

Args:
    q (numpy.ndarray): joint values (radians; metres for prismatic joints), ``dofs`` long.
    body (str): the body (e.g. ``"palm"``).
    reference (str): the reference body (``""``: the world); the Jacobian is expressed in
        its frame.

Returns:
    numpy.ndarray: 6 x dofs: linear rows (m per rad or m) then angular rows.

Raises:
    taskmap.Error: an unknown body or a ``q`` of the wrong length.

Example:
    >>> J = robot.jacobian(np.zeros(robot.dofs), "palm")
    >>> J.shape
    (6, 7)
)doc";

inline constexpr const char* kReachTarget =
    R"doc(Reaches a fixed palm pose, or plans a grasp with a task map (``taskmap reach``).

**With a 7-vector target**: attractor dynamics and resolved-rate IK with joint-limit and
collision terms in the null space move ``body`` (default the palm) to ``target`` from ``q0``
(paper eq. 1.1-1.19).

**With a TaskMap** (second form, ``taskmap reach --map``): the clusters are ranked by comfort
(other members and outliers stand in when no representative is reachable or every plan from
them is unsafe, ``member_tries``),
the reach is optimised over attractor points with the map's proximity and quality as the
terminal cost (``proximity_weight``, ``quality_weight``; BFGS or gradient ``descent``,
``iterations``), the plan ends on the map grasp it reached, and that grasp is re-simulated with
the map's own hand, object and options (``resimulate``; ``hold_test`` also tests it in physics).
The robot needs a scene with an object (:meth:`Robot.add_scene`); the map is in the object
frame.

Args:
    robot (Robot): the arm with its hand and scene.
    target (numpy.ndarray): first form: 7-vector palm pose in the ``reference`` body's frame
        (``"object"``: the scene's object; ``""``: the world), metres.
    map (TaskMap): second form: the task map of the mounted hand.
    body (str): first form: the body to move (default the palm).
    reference (str): first form: the frame of ``target``.
    q0 (numpy.ndarray, optional): start configuration (radians; metres for prismatic joints;
        default: the middle of the ranges).
    steps (int): control steps (300).
    dt (float): time step, seconds (0.01).
    relaxation_time (float): first form: the attractor's relaxation time, seconds (0.2).
    move_time (float): first form: seconds for the attractor to reach the target (1).
    avoid_collisions (bool): first form: the collision term in the null space.
    all_clusters (bool): second form: optimise from every reachable cluster.
    iterations (int): second form: optimiser iterations (40).
    proximity_weight (float): second form: w_map,p (1e4).
    quality_weight (float): second form: w_map,q on the map's quality relative to its best
        grasp, g_q / q* (3e4: -3e4 at the best grasp; 0 switches the quality term off).
    descent (str): second form: ``"bfgs"`` or ``"gradient"``.
    resimulate (bool, optional): second form: None re-simulates a built map (one with its
        hand and object recorded); True requires it, False skips it.
    hold_test (bool): second form: test the re-simulated grasp in physics.
    member_tries (int): second form: members of a cluster tried when its representative is
        out of reach or every plan is unsafe, then as many outliers (16; 0: representatives
        only).

Returns:
    dict: first form: ``status`` (``"reached"``, ``"not_reached"``, ``"collided"``),
    ``message``, ``q`` (steps+1 x dofs, rad), ``position_error`` (m), ``orientation_error``
    (rad), ``min_clearance`` (m, None without pairs), ``min_clearance_pair``,
    ``joint_limit_margin`` (rad). Second form: the report of ``taskmap reach --map --json``
    (``status``, ``message``, ``cluster``, ``grasp_index``, ``iterations``,
    ``iterations_to_manifold``, ``iterations_to_quality``, ``min_clearance_m``,
    ``joint_limit_margin_rad``, ``velocity_ratio``, ``collision_free``, ``ms_per_iteration``,
    ``ms_per_plan``, ``map_weights`` (proximity, quality, quality_peak q*), ``cost_history``, ``plans``, ``ranking``, ``proximity_over_movement``,
    ``quality_over_movement``, ``q_final``, ``resimulated``) and ``q``.

Raises:
    taskmap.Error: an unknown body or descent, a robot without a hand or scene object,
        ``hold_test`` with ``resimulate=False``.

Example:
    >>> r = taskmap.reach(robot, np.array([-0.07, 0, 0.02, 0.7071068, 0, 0.7071068, 0]))
    >>> r["status"]
    'reached'
    >>> plan = taskmap.reach(robot, taskmap.load("basket_humanoid.h5"))
)doc";

inline constexpr const char* kReachMap =
    R"doc(Plans a grasp with a task map: the second form of :func:`reach` above (``taskmap reach --map``).)doc";

inline constexpr const char* kPlanGrasp =
    R"doc(The grasp plan of :func:`reach` with a map, without re-simulation, as a shorter dict.

Args:
    robot (Robot): the arm with its hand and a scene with an object.
    map (TaskMap): the task map of the mounted hand (object frame).
    q0 (numpy.ndarray, optional): start configuration (radians; metres for prismatic joints;
        default: the middle of the ranges).
    all_clusters (bool): optimise from every reachable cluster.
    iterations (int): optimiser iterations (40).
    proximity_weight (float): w_map,p (1e4).
    quality_weight (float): w_map,q on g_q / q*, q* the map's best quality at its grasps (3e4).
    member_tries (int): members tried when no representative is reachable or every plan is
        unsafe (16).

Returns:
    dict: ``status``, ``message``, ``cluster``, ``grasp_index``, ``iterations``,
    ``iterations_to_manifold``, ``iterations_to_quality``, ``min_clearance_m``,
    ``joint_limit_margin_rad``, ``collision_free``, ``ms_per_iteration``, ``cost_history``,
    ``proximity_history``, ``quality_history``, ``q`` (steps+1 x dofs, rad).

Raises:
    taskmap.Error: a robot without a hand or scene object.

Example:
    >>> p = taskmap.plan_grasp(robot, m)
    >>> p["status"]
    'planned'
)doc";

inline constexpr const char* kJointLimitCost =
    R"doc(The joint-limit cost (paper eq. 1.8): 1/2 sum(((q - mid) / (upper - lower))^2).

Args:
    q (numpy.ndarray): joint values (radians; metres for prismatic joints).
    lower (numpy.ndarray): lower limits (radians; metres for prismatic joints).
    upper (numpy.ndarray): upper limits (radians; metres for prismatic joints), each above its
        lower limit.

Returns:
    float: the cost (0 at the middle of every range).

Raises:
    taskmap.Error: limits that are not finite with lower < upper, or sizes that differ.

Example:
    >>> taskmap.joint_limit_cost(np.zeros(2), -np.ones(2), np.ones(2))
    0.0
)doc";

inline constexpr const char* kCollisionCost =
    R"doc(The collision cost (paper eq. 1.9-1.10) summed over closest-point distances.

Per distance d: ``scale * zone * (zone - 2 d)`` when d < 0, ``scale * (d - zone)^2`` up to
``zone``, 0 beyond.

Args:
    distances (list of float): closest-point distances, metres (negative: penetrating).
    zone (float): the boundary distance d_B, metres.
    scale (float): the slope s (default 1).

Returns:
    float: the cost.

Raises:
    taskmap.Error: ``zone`` not above 0 (with at least one distance).

Example:
    >>> taskmap.collision_cost([0.05], zone=0.1)
    0.0025000000000000005
)doc";

inline constexpr const char* kValidate =
    R"doc(Tests in physics whether a map's grasps hold, as ``taskmap validate`` does, and stores the labels.

DexGraspBench's protocol in MuJoCo (docs/VALIDATION.md): the hand closes on a free object, then
six pushes of 10 N/kg along the object's axes; a grasp holds when the object moves less than
5 cm and 15 degrees. The labels (``/grasps/hold`` ...) are written into the map, or into
``output``; :attr:`TaskMap.hold` reads them.

Args:
    map (str): the map file.
    hand (str): the hand's model file (default: the map's, at its recorded path or a bundled
        hand with the same SHA-256).
    output (str): write the labelled map here instead.
    threads (int): 0 all cores (labels do not depend on it).
    grasps (int): test only the first N (0 all).
    object_mass (float): kg (0.1).
    friction (float): sliding friction (0.6).
    jaw_force (float): N per parallel jaw (70).
    contact_patch (float): metres; jaw pads split into cells of this size (0: one contact).
    robust (bool): also the robust label: the palm 1 mm and 2 degrees off along and about each
        axis, friction 0.5, a second decomposition, each within 1 cm and 5 degrees.
    full (bool): run every push its whole 2 s (default: a push ends once the object settled).
    stated_dynamics (bool): an MJCF hand's own masses, gains, damping and friction where its
        model states them (False: the protocol's).
    integrator (str): ``"implicit"`` (every map's labels so far) or ``"implicitfast"``
        (DexGraspBench's, about 1.3 times faster).
    progress (callable, optional): called about every 0.25 s with ``done``, ``total``,
        ``holding``.

Returns:
    dict: the summary of ``taskmap validate --json``: ``tested``, ``holding``, ``hold_rate``,
    ``force_closure_tested``, ``force_closure_holding``, ``statuses``, ``slipped_by_direction``,
    ``object_pieces``, ``object_volume_error``, ``object_note``, ``cpu_seconds``,
    ``wall_seconds``, ``grasps_per_cpu_second``, ``steps``; with ``robust`` also ``robust``,
    ``robust_rate``, ``variant_failures``.

Raises:
    taskmap.Error: a missing map or hand (saying what to pass), a bad option.
    KeyboardInterrupt: Ctrl-C; nothing is written.

Example:
    >>> s = taskmap.validate("box_fc.h5", grasps=10)
    >>> 0 <= s["hold_rate"] <= 1
    True
)doc";

inline constexpr const char* kTraceHold =
    R"doc(Grasp ``grasp``'s hold test stage by stage (``taskmap validate --trace I --json``).

The map is not written.

Args:
    map (str): the map file.
    grasp (int): the grasp's index, from 0.
    hand (str): the hand's model file (default: the map's).
    object_mass (float): kg.
    friction (float): sliding friction.
    jaw_force (float): N per parallel jaw.
    contact_patch (float): metres.

Returns:
    dict: ``status``, ``holds``, ``max_translation`` (m), ``max_rotation`` (rad),
    ``failed_direction``, ``initial_penetration``, ``approach`` (palm frame) and ``samples``,
    one after each closing stage and each check of the pushes: ``phase``, ``step``,
    ``translation``, ``rotation``, ``offset`` (palm frame, m), ``along_approach`` (m),
    ``contacts`` (link name: newtons).

Raises:
    taskmap.Error: a missing map or hand, or a grasp index out of range.

Example:
    >>> t = taskmap.trace_hold("box_fc.h5", 0)
    >>> t["samples"][-1]["phase"]
)doc";

inline constexpr const char* kSummary = R"doc(What ``taskmap inspect --json MAP`` prints, as a dict.

Args:
    map (str or TaskMap): a map file, or a loaded map (then ``path`` is ``""``).

Returns:
    dict: ``path``, ``generator``, ``created_utc``, ``object`` (``name``, ``vertices``,
    ``faces``, ``volume`` m^3, ``bounds_min``, ``bounds_max`` m), ``hand`` (``name``,
    ``joints``), ``sampling`` (``sampler``, ``seed``, ``trials``, ``outcomes``), ``grasps``
    (``count``, ``force_closure``, ``valid_rate``, ``contacts_available``, ``rotation_scale``
    m/rad), ``epsilon`` (``count``, ``min``, ``median``, ``max``), ``clustering`` (None, or
    ``linkage``, ``threshold`` m, ``min_size``, ``outliers`` and ``clusters``: ``id``,
    ``size``, ``representative``, ``pose`` (palm in the object frame), ``approach``,
    ``mean_epsilon``, ``best_epsilon``, ``color``).

Raises:
    taskmap.Error: a missing file or one that is not a task map.

Example:
    >>> taskmap.summary("basket.h5")["grasps"]["count"]
)doc";

inline constexpr const char* kHandInit =
    R"doc(Drafts a hand sidecar from the model alone, as ``taskmap hand-init`` does.

Palm link, palm frame and approach axis from where the fingers close, closing joints and
directions, fingers, preshape (docs/METHOD.md, "Drafting a sidecar").

Args:
    urdf (str): the hand's URDF or MJCF.
    output (str, optional): also write the JSON there (atomically).
    force (bool): replace an existing ``output``.
    package_path (list of str): folders where ``package://`` mesh paths are looked up first.

Returns:
    dict: ``sidecar`` (the draft as a dict), ``json`` (its text), ``notes`` (one line per
    guess: the field, its value and why).

Raises:
    taskmap.Error: a missing file, an existing ``output`` without ``force``, or fields the
        draft cannot decide (named).

Example:
    >>> d = taskmap.hand_init("my_hand.urdf", output="my_hand.hand.json")
    >>> d["sidecar"]["approach_axis"]
)doc";

inline constexpr const char* kMeshInfo =
    R"doc(What ``taskmap mesh-info --json FILE`` reports about an object loaded as a solid.

Args:
    file (str): a mesh file (any format assimp reads) or a bundled object's name.
    scale (float): file units to metres.
    no_repair (bool): refuse a mesh that needs repair.
    repair (str): ``"wrap"`` also closes an open surface by alpha wrapping.
    wrap_alpha (float): metres (0: automatic).
    wrap_offset (float): metres (0: automatic).

Returns:
    dict: ``path``, ``format``, ``sha256``, ``scale``, ``input_vertices``, ``input_faces``,
    ``vertices``, ``faces``, ``repairs``, ``warnings``, ``size`` (m), ``graspable_size``,
    ``closed``, ``volume`` (m^3), ``bounds_min``, ``bounds_max``, ``center_of_mass`` (m, object
    frame), ``inertia`` (3 rows, kg m^2 at density 1 kg/m^3, about the centre of mass),
    ``torque_scale`` (m).

Raises:
    taskmap.Error: a missing file (with the closest names) or one that does not load as a
        solid.

Example:
    >>> taskmap.mesh_info("basket")["closed"]
    True
)doc";

inline constexpr const char* kHandInfo =
    R"doc(What ``taskmap hand-info --json HAND`` reports, as a dict; optionally draws the hand.

Args:
    hand (str): a hand's URDF or MJCF (sidecar beside it), or a bundled hand's name.
    png (str): also draw it open and closed, three views each (PNG).
    html (str): also write the interactive 3-D page.
    package_path (list of str): folders where ``package://`` mesh paths are looked up first.

Returns:
    dict: ``name``, ``robot_name``, ``urdf``, ``sidecar``, ``urdf_sha256``, ``joints``
    (``name``, ``type``, ``parent``, ``child``, ``lower``, ``upper`` in rad or m, ``axis``,
    ``mimic`` or ``actuated``, ``preshape``, ``closed``), ``closing``, ``palm_link``,
    ``palm_frame`` (``xyz`` m, ``rpy`` rad, in the palm link), ``root_to_palm``,
    ``approach_axis`` (palm frame), ``rotation_scale`` (m/rad), ``reach`` (m), ``squeeze``,
    ``fingers``, ``links``, ``collision_meshes`` (volumes m^3), ``warnings`` (set-ups that
    cannot grasp), ``notes``.

Raises:
    taskmap.Error: a hand that does not load, naming the file.

Example:
    >>> taskmap.hand_info("barrett")["warnings"]
    []
)doc";

inline constexpr const char* kPicture =
    R"doc(Draws a map to a PNG: the picture of ``taskmap inspect MAP --png PNG``.

Three orthographic views of the object with the palm positions coloured by cluster, each
cluster representative with its approach axis and the outline of the hand posed by it, and an
epsilon histogram per cluster. Written atomically.

Args:
    map (str or TaskMap): a map file or a loaded map.
    png (str): the file to write.
    hand (str): the hand to outline (default: the map's, found by its SHA-256; a warning and no
        hand when none is found).
    width (int): pixels, >= 800 (1600).
    height (int): pixels, >= 600 (1100).

Returns:
    str: ``png``.

Raises:
    taskmap.Error: a bad map, hand or size.

Example:
    >>> taskmap.picture("basket.h5", png="basket.png")
    'basket.png'
)doc";

inline constexpr const char* kExport =
    R"doc(Writes a map as a scene or an ACRONYM file, as ``taskmap export`` does.

``"ply"``/``"glb"``: the object mesh, the palm positions coloured by cluster, a hand glyph per
cluster representative and the hand's collision shapes posed by each representative.
``"acronym"``: ACRONYM's per-object HDF5 layout, the palm frame converted to the gripper's base
frame (docs/ACRONYM.md).

Args:
    map (str or TaskMap): a map file or a loaded map.
    format (str): ``"ply"``, ``"glb"`` or ``"acronym"``.
    output (str): the file to write (never an input).
    glyph_size (float): ply/glb: finger length of the glyphs, metres (0: automatic).
    density (float): acronym: the object's density, kg/m^3 (1000).
    object_file (str): acronym: the mesh name recorded (default ``<object name>.obj``).
    palm_offset (float, optional): acronym: the palm this far along the base's z, metres.
    hand (str): the hand to draw (ply/glb) or whose root-to-palm converts (acronym).
    force (bool): replace an output that is not of the format written.

Returns:
    str: ``output``.

Raises:
    taskmap.Error: a bad map, format or argument, naming it.

Example:
    >>> taskmap.export("basket.h5", format="glb", output="basket.glb")
    'basket.glb'
)doc";

inline constexpr const char* kExportGlb =
    R"doc(Writes a trajectory file as an animated glTF scene, as ``taskmap export-glb`` does.

One node per body with its collision primitives, the object mesh, and the animation ``reach``
over the steps (z-up world turned to glTF's y-up); opens in Blender.

Args:
    trajectory (str): a trajectory file (``taskmap reach --map ... -o``).
    output (str): the .glb to write (atomically).
    force (bool): replace an output that is not a GLB file.

Returns:
    str: ``output``.

Raises:
    taskmap.Error: a missing or damaged trajectory, naming it.

Example:
    >>> taskmap.export_glb("reach.h5", output="reach.glb")
    'reach.glb'
)doc";

inline constexpr const char* kView =
    R"doc(Writes one self-contained interactive HTML page, as ``taskmap view`` does.

three.js is embedded and the page opens offline. A map: the hand's collision shapes posed by
each grasp on the object, coloured by cluster, with filters and contacts; a trajectory: the
movement with a time slider and the cost terms, the map's hand closing to the chosen grasp at
the end (docs/VIEWING.md).

Args:
    file (str): a task map or a trajectory file.
    output (str, optional): the page (default ``<file stem>.html`` in the working directory).
    hand (str): the hand to draw a map's grasps or a trajectory's grasp with (default: the
        map's, found by its SHA-256; a warning and palms only, or the planner's primitives of
        the hand, when none is found).
    ghosts (int): most hands drawn at once (60).
    title (str): the page title.

Returns:
    str: the page's path.

Raises:
    taskmap.Error: a missing file or a bad argument.

Example:
    >>> taskmap.view("basket.h5", output="basket.html")
    'basket.html'
)doc";

}  // namespace taskmap::pydoc
