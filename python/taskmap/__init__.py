"""Grasp task maps (Gienger, Toussaint, Goerick, section 1.6): load a map, query its nearest
grasps and its mixture-of-Gaussians quality with gradients; build maps and data sets of maps, plan
reaches and validate grasps.

``import taskmap`` loads the run-time query library only (``taskmap._core``: the map store and
the FLANN index), none of Bullet, assimp, qhull, urdfdom, CGAL, cairo or MuJoCo. The offline
stages (``build``, ``dataset``, ``import_acronym``, ``recluster``, ``regress``, ``Robot``,
``reach``, ``plan_grasp``, ``validate``, ``trace_hold``, the robot's comfort costs ``joint_limit_cost`` and
``collision_cost``, and ``summary``, ``hand_info``, ``hand_init``, ``mesh_info``, ``picture``,
``export``, ``export_glb``, ``view``: what ``taskmap inspect``, ``hand-info``, ``hand-init``,
``mesh-info``, ``export``, ``export-glb`` and ``view`` report, draw and write) live in
``taskmap._offline`` and are imported on first use of one of their names.

Poses are numpy arrays ``[x, y, z, qw, qx, qy, qz]`` (metres, unit quaternion) of the hand in the
object frame unless a function says otherwise; gradients are 6-vectors (linear, angular).
Errors in input or usage raise ``taskmap.Error`` (a ``ValueError``) naming the file or option.
"""
from ._core import *  # noqa: F401,F403  (the run-time queries)
from ._core import Error, TaskMap, Session, load, seal  # noqa: F401

__version__ = "0.1.0"

# Names provided by taskmap._offline, imported when first used (PEP 562).
_OFFLINE = frozenset({"build", "dataset", "import_acronym", "Robot", "reach", "plan_grasp",
                      "validate", "trace_hold", "joint_limit_cost", "collision_cost", "summary", "hand_info",
                      "mesh_info", "hand_init", "recluster", "regress", "picture",
                      "export", "export_glb", "view"})


def __getattr__(name):
    if name in _OFFLINE:
        from . import _offline
        value = getattr(_offline, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'taskmap' has no attribute '{name}'")


def __dir__():
    return sorted(set(globals()) | _OFFLINE)
