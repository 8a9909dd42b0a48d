"""The UR5e motions of the project's library, generated from Cartesian waypoints.

Two generators return a :class:`~motiontool.motionfmt.Motion` over the six UR5e motors (model
order: ``shoulder_pan_joint``, ``shoulder_lift_joint``, ``elbow_joint``, ``wrist_1_joint``,
``wrist_2_joint``, ``wrist_3_joint``), values in rad, times in integer ms:

* :func:`sorting_motion`: the sorting task of the Webots lesson that introduced the arm;
* :func:`jog_motion`: home → jog each joint → home, like the lesson's keyboard jog.

Both begin at the robot's start pose (every joint at 0 rad) and move to home first.

No joint value is typed in: the sorting keyframes come from inverse kinematics
(:func:`motiontool.kinematics.ik.solve_ik`) of the tool flange, the jog keyframes from the jog
rule applied to the IK home pose. ``motiontool generate ur5e-sorting`` / ``ur5e-jog`` rewrite
``motions/ur5e/*.motion``; the tests check that the committed files are what these functions
produce.

The scene (world frame: z up, floor at z = 0, x in front of the robot, y to its left; metres):

* the robot stands on a 0.6 m wooden box: its base frame is the world frame moved up to
  ``BASE_POSITION_M`` = (0, 0, 0.6), axes unrotated (Webots' ``ure.wbt`` puts the UR5e at
  (0, 0, 0.61) on a 0.61 m box; the lesson's box is 0.6 m);
* items (Webots ``Can``: 0.122 m tall) arrive at the pick-up point ``PICK_XY_M`` = (0.55, 0)
  on a conveyor whose belt is at ``TABLE_TOP_Z_M`` = 0.6 (the height of the belts in
  ``ure.wbt``), 0.55 m in front of the robot;
* two crates on the floor, rim at ``BIN_RIM_Z_M`` = 0.4: rusty items go to the left one,
  centred at ``BINS_XY_M['rusty']`` = (0, 0.55), galvanized items to the right one at
  ``BINS_XY_M['galvanized']`` = (0, -0.55);
* the flange (frame ``tool_slot``: the Webots ``toolSlot``, 0.1 m along wrist_3's y axis) points
  straight down whenever it is at a waypoint, its x axis horizontal and square to the line from
  the base to the waypoint (so the wrist barely turns). Heights of the flange: grasp at
  ``GRASP_Z_M`` = 0.80 (0.2 m above the belt: the gripper's fingers close around the upper half
  of the can), release at ``PLACE_Z_M`` = 0.70 (0.3 m above the crate's rim), travel at
  ``TRAVEL_Z_M`` = 0.95; home at ``HOME_M`` = (0.35, 0, 1.05).

The sequence (``ITEMS``: rusty, galvanized, rusty): home, then per item: above the pick-up
point, down, grasp (a pause), up, over the item's bin, down, release (a pause), up; then home.

Where each pick and place is reached (:func:`sorting_expectations`, the ``[sorting]``
expectations of ``motions/motions.toml``, checked by ``motiontool batch motions/``): the tool
comes within 1 mm of the pick before the grasp pause ends (``ee_lag[pick_N]<480ms``), and at the
end of each grasp and release pause it is within ``REACH_TOLERANCE_MM`` of both the forward
kinematics of the keyframe (``ee_error``) and the stated Cartesian target (``ee[...]=[x,y,z]``).

Timing: each segment gets the shortest duration, a multiple of the UR5e world's 8 ms time step,
with every joint at most ``SPEED_MARGIN`` (0.5) × its maxVelocity, and at least
``MIN_SEGMENT_MS``; pauses last ``GRASP_MS`` and ``RELEASE_MS``. Joint values are rounded to
``VALUE_DECIMALS`` decimals (1 µrad, a few µm at the flange), which keeps the files readable
and their regeneration byte-stable.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.kinematics.ik import Pose, forward_pose, solve_ik
from motiontool.kinematics.robots import RobotSpec, load_robot
from motiontool.motionfmt.motion import Motion
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = [
    "BASE_POSITION_M",
    "BINS_XY_M",
    "BIN_RIM_Z_M",
    "FLANGE_FRAME",
    "GRASP_Z_M",
    "HOME_M",
    "ITEMS",
    "PICK_XY_M",
    "PLACE_Z_M",
    "REACH_TOLERANCE_MM",
    "TABLE_TOP_Z_M",
    "TRAVEL_Z_M",
    "Task",
    "Waypoint",
    "flange_pose",
    "generate",
    "jog_motion",
    "peak_speeds",
    "segment_ms",
    "sorting_expectations",
    "sorting_motion",
    "sorting_plan",
    "sorting_spots",
    "tool_down",
]

ROBOT = "ur5e"
#: The tool flange: the Webots toolSlot frame (site ``tool_slot`` of the model).
FLANGE_FRAME = "tool_slot"

# ----------------------------------------------------------------------- the scene (world, m)
BASE_POSITION_M = (0.0, 0.0, 0.6)
TABLE_TOP_Z_M = 0.6
PICK_XY_M = (0.55, 0.0)
BINS_XY_M: Mapping[str, tuple[float, float]] = {"rusty": (0.0, 0.55), "galvanized": (0.0, -0.55)}
BIN_RIM_Z_M = 0.4
GRASP_Z_M = 0.80
PLACE_Z_M = 0.70
TRAVEL_Z_M = 0.95
HOME_M = (0.35, 0.0, 1.05)
ITEMS = ("rusty", "galvanized", "rusty")

# ----------------------------------------------------------------------- timing
#: Fraction of each motor's maxVelocity a keyframe segment may use.
SPEED_MARGIN = 0.5
#: Shortest move, ms: short moves still take this long, so the arm does not jerk.
MIN_SEGMENT_MS = 400
#: How long the gripper closes on an item / opens over a bin, ms.
GRASP_MS = 480
RELEASE_MS = 320
#: Decimals kept of each joint value (rad).
VALUE_DECIMALS = 6
#: How close the tool must be to a pick or place target at the end of its pause, mm: the
#: gripper's fingers close around a can 66 mm across; a few mm off is still a grasp.
REACH_TOLERANCE_MM = 5.0

#: The IK branch of the first waypoint: shoulder raised, elbow up, wrist down, tool facing
#: down in front of the robot. Only a starting point: the first waypoint is solved from it, every
#: later one from its predecessor's solution. Not written to any file. rad, model order.
BRANCH_SEED = (0.0, -1.2, 1.8, -2.2, -1.57, 0.0)

# ----------------------------------------------------------------------- jog
#: The lesson's keyboard jog: 0.01 rad per key step, one step every 64 ms.
JOG_STEP_RAD = 0.01
JOG_STEP_MS = 64
#: Steps up (then as many back down) for each joint: 10 × 0.01 rad = 0.1 rad.
JOG_STEPS = 10


class Task(enum.StrEnum):
    """The motions ``motiontool generate`` can write."""

    sorting = "ur5e-sorting"
    jog = "ur5e-jog"


@dataclass(frozen=True)
class Waypoint:
    """One keyframe of the sorting task.

    Attributes:
        name: the pose name written to the file (``pick_1``, ``release_2``, ...).
        spot: the Cartesian flange pose it goes to, a key of :func:`sorting_spots`.
        pause_ms: None for a move (timed by the joint speeds), or the fixed duration of a
            pause at the same spot (grasp, release), ms.
    """

    name: str
    spot: str
    pause_ms: int | None = None


def tool_down(position_m: Sequence[float]) -> Pose:
    """Flange pose at ``position_m`` (world, m): flange normal (its y axis) pointing down,
    its x axis horizontal, square to the horizontal line from the base to the point."""
    import numpy as np

    x, y, z = (float(v) for v in position_m)
    heading = math.atan2(y - BASE_POSITION_M[1], x - BASE_POSITION_M[0]) - math.pi / 2
    x_axis = np.array([math.cos(heading), math.sin(heading), 0.0])
    y_axis = np.array([0.0, 0.0, -1.0])
    return Pose(np.array([x, y, z]), np.column_stack([x_axis, y_axis, np.cross(x_axis, y_axis)]))


def sorting_spots() -> dict[str, Pose]:
    """The Cartesian waypoints of the sorting task: flange poses in the world frame."""
    px, py = PICK_XY_M
    spots = {
        "home": tool_down(HOME_M),
        "above_pick": tool_down((px, py, TRAVEL_Z_M)),
        "pick": tool_down((px, py, GRASP_Z_M)),
    }
    for kind, (bx, by) in BINS_XY_M.items():
        spots[f"above_{kind}_bin"] = tool_down((bx, by, TRAVEL_Z_M))
        spots[f"in_{kind}_bin"] = tool_down((bx, by, PLACE_Z_M))
    return spots


def sorting_plan(items: Sequence[str] = ITEMS) -> list[Waypoint]:
    """The keyframes of the sorting task for ``items`` (each ``rusty`` or ``galvanized``)."""
    plan = [Waypoint("home", "home")]
    for n, kind in enumerate(items, start=1):
        if kind not in BINS_XY_M:
            raise MotionToolError(f"unknown item kind '{kind}'; choose one of rusty, galvanized")
        above_bin, in_bin = f"above_{kind}_bin", f"in_{kind}_bin"
        plan += [
            Waypoint(f"above_pick_{n}", "above_pick"),
            Waypoint(f"pick_{n}", "pick"),
            Waypoint(f"grasp_{n}", "pick", GRASP_MS),
            Waypoint(f"lift_{n}", "above_pick"),
            Waypoint(f"over_{kind}_bin_{n}", above_bin),
            Waypoint(f"place_{n}", in_bin),
            Waypoint(f"release_{n}", in_bin, RELEASE_MS),
            Waypoint(f"leave_{kind}_bin_{n}", above_bin),
        ]
    plan.append(Waypoint("home", "home"))
    return plan


def sorting_expectations(items: Sequence[str] = ITEMS) -> list[str]:
    """Where the sorting task must reach each pick and place, as expectations of its play
    report (docs/play.md, "Expectations"): the pick within 1 mm (the default reach tolerance) before
    the grasp pause ends, and at the end of each pause the tool within
    :data:`REACH_TOLERANCE_MM` of the keyframe's forward kinematics and of the stated target
    (:func:`sorting_spots`, world frame, m)."""
    spots = sorting_spots()
    tol = f"{REACH_TOLERANCE_MM:g}mm"
    out = []
    for waypoint in sorting_plan(items):
        if waypoint.name.startswith("pick_"):
            out.append(f"ee_lag[{waypoint.name}]<{GRASP_MS}ms")
        if waypoint.pause_ms is not None:  # grasp_N, release_N: the pause at the spot
            x, y, z = (round(float(v), 6) + 0.0 for v in spots[waypoint.spot].position)
            out.append(f"ee_error[{waypoint.name}]<{tol}")
            out.append(f"ee[{waypoint.name}]=[{x:g},{y:g},{z:g}]±{tol}")
    return out


def _base_frame(pose: Pose) -> Pose:
    import numpy as np

    return Pose(pose.position - np.array(BASE_POSITION_M), pose.rotation)


def flange_pose(spec: RobotSpec, q_by_joint: Mapping[str, float]) -> Pose:
    """The flange's pose in the world frame (the robot on its box) for these motor positions
    (rad)."""
    import numpy as np

    pose = forward_pose(spec, q_by_joint, FLANGE_FRAME)
    return Pose(pose.position + np.array(BASE_POSITION_M), pose.rotation)


def segment_ms(
    start: Sequence[float],
    end: Sequence[float],
    max_velocity: Sequence[float],
    *,
    margin: float = SPEED_MARGIN,
    min_ms: int = MIN_SEGMENT_MS,
    step_ms: int = 8,
) -> int:
    """Shortest duration (ms, a multiple of ``step_ms``, at least ``min_ms``) in which every
    joint goes from ``start`` to ``end`` (rad) at no more than ``margin × max_velocity`` (rad/s).
    """
    import numpy as np

    delta = np.abs(np.asarray(end, dtype=np.float64) - np.asarray(start, dtype=np.float64))
    limit = margin * np.asarray(max_velocity, dtype=np.float64)
    need_ms = float(np.max(delta / limit)) * MS_PER_S
    ms = max(min_ms, step_ms * math.ceil(need_ms / step_ms))
    ms = step_ms * math.ceil(ms / step_ms)
    while np.any(delta / (ms / MS_PER_S) > limit):  # guard against rounding at the boundary
        ms += step_ms
    return ms


def _solve_spots(spec: RobotSpec, plan: Sequence[Waypoint]) -> dict[str, list[float]]:
    """IK of every spot the plan visits, each solved once, seeded from the previous spot's
    solution in the order the plan first reaches them (the first from ``BRANCH_SEED``)."""
    spots = sorting_spots()
    names = spec.joint_names
    seed = dict(zip(names, BRANCH_SEED, strict=True))
    solved: dict[str, list[float]] = {}
    for waypoint in plan:
        if waypoint.spot in solved:
            seed = dict(zip(names, solved[waypoint.spot], strict=True))
            continue
        solution = solve_ik(spec, _base_frame(spots[waypoint.spot]), seed, frame=FLANGE_FRAME)
        values = [round(v, VALUE_DECIMALS) for v in solution.values(names)]
        solved[waypoint.spot] = values
        seed = dict(zip(names, values, strict=True))
    return solved


def _checked_motion(
    spec: RobotSpec, pose_names: list[str], times: list[int], rows: list[list[float]]
) -> Motion:
    import numpy as np

    for name, row in zip(pose_names, rows, strict=True):
        for joint, value in zip(spec.joints, row, strict=True):
            if not joint.lower <= value <= joint.upper:
                raise MotionToolError(
                    f"pose '{name}': {joint.name} = {value} rad is outside "
                    f"[{joint.lower}, {joint.upper}] rad"
                )
    return Motion(spec.joint_names, tuple(pose_names), np.array(times), np.array(rows))


def _from_start(
    spec: RobotSpec, names: list[str], times: list[int], rows: list[list[float]]
) -> tuple[list[str], list[int], list[list[float]]]:
    """Begin at the pose the robot starts in (every joint at 0 rad, as the UR5e spawns in Webots)
    and move to the first pose in the shortest segment within the speed margin, instead of
    commanding the first pose at once (validate's MT206 trap, hidden at t = 0)."""
    start = [0.0] * len(spec.joints)
    lead = segment_ms(
        start, rows[0], [j.max_velocity for j in spec.joints], step_ms=spec.default_timestep_ms
    )
    return ["start", *names], [0, *(t + lead for t in times)], [start, *rows]


def sorting_motion(items: Sequence[str] = ITEMS) -> Motion:
    """The sorting task (see the module docstring) for ``items``."""
    spec = load_robot(ROBOT)
    plan = sorting_plan(items)
    solved = _solve_spots(spec, plan)
    max_velocity = [j.max_velocity for j in spec.joints]
    times, rows = [0], [solved[plan[0].spot]]
    for waypoint in plan[1:]:
        row = solved[waypoint.spot]
        duration = waypoint.pause_ms or segment_ms(
            rows[-1], row, max_velocity, step_ms=spec.default_timestep_ms
        )
        times.append(times[-1] + duration)
        rows.append(row)
    return _checked_motion(spec, *_from_start(spec, [w.name for w in plan], times, rows))


def jog_motion(steps: int = JOG_STEPS) -> Motion:
    """Home, then each joint in turn ``steps`` × 0.01 rad up and back, one 0.01 rad step every
    64 ms with the other joints held, ending at home. Home is the sorting task's IK home."""
    if steps < 1:
        raise MotionToolError(f"the jog needs at least 1 step, got {steps}")
    spec = load_robot(ROBOT)
    home = _solve_spots(spec, [Waypoint("home", "home")])["home"]
    names, times, rows = ["home"], [0], [home]
    for j, joint in enumerate(spec.joint_names):
        for k in [*range(1, steps + 1), *range(steps - 1, -1, -1)]:
            row = list(home)
            row[j] = round(home[j] + k * JOG_STEP_RAD, VALUE_DECIMALS)
            names.append(f"{joint}+{k}" if k else "home")
            times.append(times[-1] + JOG_STEP_MS)
            rows.append(row)
    return _checked_motion(spec, *_from_start(spec, names, times, rows))


def peak_speeds(motion: Motion) -> npt.NDArray[np.float64]:
    """Largest keyframe-segment speed of each joint, rad/s, shape (J,) float64 (0 for a single
    pose; segments touching a ``*`` cell are skipped)."""
    import numpy as np

    if motion.n_poses < 2:
        return np.zeros(motion.n_joints)
    dt_s = np.diff(motion.times_ms).astype(np.float64)[:, None] / MS_PER_S
    speeds = np.abs(np.diff(motion.values, axis=0)) / dt_s
    return np.asarray(np.nanmax(np.where(np.isnan(speeds), 0.0, speeds), axis=0))


_GENERATORS: Mapping[Task, Callable[[], Motion]] = {
    Task.sorting: sorting_motion,
    Task.jog: jog_motion,
}


def generate(task: Task | str) -> Motion:
    """The motion of ``task`` (``ur5e-sorting`` or ``ur5e-jog``)."""
    try:
        chosen = Task(task)
    except ValueError:
        choices = ", ".join(t.value for t in Task)
        raise MotionToolError(f"unknown task '{task}'; choose one of {choices}") from None
    return _GENERATORS[chosen]()
