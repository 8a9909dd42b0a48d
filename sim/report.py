"""The report of a ``play`` run, and its JSON form (schema ``motiontool.play``, version 1).

JSON schema (every number carries its unit in its key or in the ``unit`` next to it)::

    {
      "schema": "motiontool.play", "schema_version": 1,
      "stamps": {"motiontool", "mujoco", "pinocchio", "rerun", "numpy": versions,
                 "model_sha256": hex, "control_step_ms", "physics_step_ms", "seed"},
      "robot": "nao",
      "files": [{"path", "start_s", "duration_s", "steps",     # one per motion played, in order
                 "loops",                                      #   (an element of a chain)
                 "dx_m", "dy_m", "distance_m",                 # its base's motion, start to end
                 "yaw_change_deg"}],                           #   (null: a fixed-base robot)
      "options": {"loops", "reverse", "start", "p_gain_per_s", "hold_s", "floor_friction",
                  "mass_scale", "torque_scale", "start_yaw_deg", "start_noise_rad",
                  "fall_height_m", "fall_tilt_deg", "collision_tolerance_mm"},
      "physics": {"timestep_ms", "friction",                     # as the compiled model has them
                  "profile" ("default"|"webots"),
                  "profile_note"},                               # webots only: not what makes
                                                                 #   walks match (docs/play.md);
                                                                 #   with --friction/--physics-step:
                                                                 #   what ran instead
      "world": null | {"path", "sha256", "version",              # play --world FILE.wbt
                "robot_node": {"name", "def", "type"},           # the node that played
                "applied": [{"field", "value", "unit", "applied_as"}],
                "not_applied": [{"field", "value", "unit", "reason"}],
                "skipped_nodes": ["why: nodes"]},                # nodes not simulated
      "self_collision": null | {"physics",                       # robot parts collide (bool)
                "source" ("option"|"world"|"robot model"), "why",
                "touching_pairs", "touching_s"},   # pairs of robot bodies that touched in the
                                                   #   simulation, their summed contact time
      "simulated_s": 7.78, "control_steps": 389,
      "clean": true, "exit_code": 0, "reason": "",               # reason: '; '-joined, '' if clean
      "error": null,                                             # why the run stopped early
      "base": null | {                                           # free-flying robots only
        "dx_m", "dy_m", "dz_m",              # root displacement, start -> end, world frame
        "yaw_change_deg",                    # heading change over the upright part (unwrapped)
        "max_tilt_deg", "final_tilt_deg",    # angle between the root's z axis and the vertical
        "min_height_m", "final_height_m",    # root height above the floor
        "started_down", "fell", "fell_at_s", "upright_at_end",
        "fall_direction_deg"},               # which way it fell, from its heading just before:
                                             #   0 forward, 90 left, -90 right, 180 back
                                             #   (null: it did not fall)
      "end_effector": null | {                                   # fixed-base robots only
        "frame", "kind" ("site"|"body"),     # the tool: a site named tool/tcp/ee/flange/...,
                                             #   else the last body of the chain
        "reach_tolerance_mm",                # what "reached" means for lag_ms
        "keyframes": [{"file_index", "name", "time_s",   # every keyframe the run reached,
                                                         #   once, in the order first played;
                                                         #   its worst visit (--loop repeats)
                       "commanded_position_m", "commanded_quat_wxyz",  # FK of its targets
                       "measured_position_m", "measured_quat_wxyz",    # at time_s
                       "position_error_mm", "orientation_error_deg",
                       "lag_ms",             # after time_s, when the tool first came within
                                             #   the tolerance, the longest of the visits (null:
                                             #   a visit did not before the motion went on to
                                             #   another position, or the end)
                       "visits",             # how many times the run reached it
                       "measured_box_m"}],   # [[min x, y, z], [max x, y, z]] of the visits
        "max_deviation_mm", "max_deviation_at_s",  # tool vs FK of the command stream
        "trail_time_s": [...], "trail_position_m": [[x, y, z], ...]},  # the tool's path,
                                  # about every 50 ms (arm.TRAIL_POINTS at most: a longer
                                  # run's samples are every 100 ms, 200 ms, ...)
      "joints": [{"name", "limb", "unit" ("rad"|"m"), "commanded",
                  "rms_error", "max_error",          # target (clipped) - position, in "unit"
                  "velocity_cap_s", "torque_cap_s",  # time with |Vc| at maxVelocity / |torque|
                                                     # at maxTorque (sampled every control step)
                  "target_clipped_s",                # time the target lay outside the limits
                  "beyond_limits_s"}],               # time the position lay outside the limits
      "feet": [{"name", "contact_s", "slip_m",          # slip: horizontal travel while touching
                "max_displacement_m", "final_displacement_m"}],   # horizontal, from the start
      "self_collisions": [{"body_a", "body_b", "first_s", "duration_s", "max_depth_m"}],
                                        # pairs of robot bodies interpenetrating by at least
                                        # options.collision_tolerance_mm
      "scene_contacts": [...same...],   # the robot touching anything but the floor
      "ground_contacts": [...same...],  # robot bodies other than the feet touching the floor
      "warnings": {"bad_qacc": 0, ...}, # MuJoCo warning counters over the run
      "ignored_joints": ["..."],        # motion columns that are not motors of the robot
      "unplayed_files": ["..."],        # motions none of whose columns is a motor of the robot
                                        #   (nothing of them was played: the run is not clean)
      "expectations": [{"text", "quantity", "joint", "expected", "passed",   # motiontool.sim.expect
                        "measured": {"value", "unit"}, "reason"}]         # (reason: '' if passed)
    }

A failed expectation makes the run not clean (its reason joins ``reason``); an expectation that
names the fall (``fell``, ``no-fall``, ``fell_at``) replaces the fall verdict.

Times are simulated seconds from the start of the run. No wall-clock time is reported: the same
inputs give the same report, bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields
from pathlib import PurePath
from typing import TYPE_CHECKING, Any, TypeVar

from motiontool import exit_codes

if TYPE_CHECKING:
    from collections.abc import Sequence

    from motiontool.sim.expect import ExpectationResult

__all__ = [
    "SCHEMA",
    "SCHEMA_VERSION",
    "BaseStats",
    "ContactSummary",
    "EndEffectorStats",
    "FileRun",
    "FootStats",
    "JointStats",
    "KeyframePose",
    "PlayReport",
]

SCHEMA = "motiontool.play"
SCHEMA_VERSION = 1

_T = TypeVar("_T")


@dataclass(frozen=True)
class FileRun:
    """One motion of the sequence (an element of a chain): where it starts (s), how long it
    plays (s), its steps, its cycles; for a free-flying robot, what its base did from the
    frame the motion starts at to the frame it ends at (None: not measured): the displacement
    (m, world frame), its length (m) and the heading change (degrees, + = left)."""

    path: str
    start_s: float
    duration_s: float
    steps: int
    loops: int = 1
    dx_m: float | None = None
    dy_m: float | None = None
    distance_m: float | None = None
    yaw_change_deg: float | None = None


@dataclass(frozen=True)
class JointStats:
    """Tracking of one motor (errors in ``unit``: rad for hinges, m for slides)."""

    name: str
    limb: str
    unit: str
    commanded: bool
    rms_error: float
    max_error: float
    velocity_cap_s: float
    torque_cap_s: float
    target_clipped_s: float
    beyond_limits_s: float


@dataclass(frozen=True)
class FootStats:
    """One foot: time on the floor (s), slip while on it (m), displacement from the start (m)."""

    name: str
    contact_s: float
    slip_m: float
    max_displacement_m: float
    final_displacement_m: float


@dataclass(frozen=True)
class ContactSummary:
    """A contact (or interpenetration) over the run: first seen (s), total duration (s), depth."""

    body_a: str
    body_b: str
    first_s: float
    duration_s: float
    max_depth_m: float


@dataclass(frozen=True)
class BaseStats:
    """What the root body of a free-flying robot did (see the module docstring)."""

    dx_m: float
    dy_m: float
    dz_m: float
    yaw_change_deg: float | None
    max_tilt_deg: float
    final_tilt_deg: float
    min_height_m: float
    final_height_m: float
    started_down: bool
    fell: bool
    fell_at_s: float | None
    upright_at_end: bool
    fall_direction_deg: float | None = None


@dataclass(frozen=True)
class KeyframePose:
    """The tool at one keyframe of a motion (world frame, m; quaternions (w, x, y, z)).

    A run that reaches a keyframe several times (``--loop``) has one entry for it: the fields
    but ``lag_ms`` are those of its visit with the largest position error, ``lag_ms`` is the
    longest of its visits', and ``measured_box_m`` holds where the tool was at every visit.
    The report stays the same size however long the run.

    Attributes:
        file_index: which motion of ``files`` the keyframe belongs to.
        name: its pose name; time_s: when the run reaches it, simulated s.
        commanded_position_m, commanded_quat_wxyz: forward kinematics of its joint targets
            (clipped to the motor limits, as the motors see them; a ``*`` cell or a joint the
            motion does not name: the target in force).
        measured_position_m, measured_quat_wxyz: the simulated tool at ``time_s`` (the first
            frame at or after it).
        position_error_mm: distance between the two positions; orientation_error_deg: angle
            between the two orientations.
        lag_ms: how long after ``time_s`` the tool first came within the reach tolerance of
            the commanded position; None when it did not before the motion went on to another
            position (the next keyframe whose commanded position is further than the
            tolerance) or the run ended; with several visits, the longest, None when one
            visit did not.
        visits: how many times the run reached the keyframe.
        measured_box_m: (min, max) corners of the box holding the measured positions of
            every visit, m; None in a report written before visits were folded.
    """

    file_index: int
    name: str
    time_s: float
    commanded_position_m: tuple[float, float, float]
    commanded_quat_wxyz: tuple[float, float, float, float]
    measured_position_m: tuple[float, float, float]
    measured_quat_wxyz: tuple[float, float, float, float]
    position_error_mm: float
    orientation_error_deg: float
    lag_ms: float | None
    visits: int = 1
    measured_box_m: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None

    def farthest_from(self, point: Sequence[float]) -> tuple[float, float, float]:
        """Where the tool was farthest from ``point`` (m) at a visit, at most: the corner of
        ``measured_box_m`` farthest from it (the measured position itself for one visit)."""
        if self.measured_box_m is None or self.visits == 1:
            return self.measured_position_m
        low, high = self.measured_box_m
        x, y, z = (
            lo if abs(lo - p) >= abs(hi - p) else hi
            for lo, hi, p in zip(low, high, point, strict=True)
        )
        return (x, y, z)


@dataclass(frozen=True)
class EndEffectorStats:
    """What the tool of a fixed-base arm did (see the module docstring).

    Attributes:
        frame: the tool's site (or body) name; kind: ``site`` or ``body``.
        reach_tolerance_mm: the distance within which a keyframe counts as reached.
        keyframes: the tool at every keyframe the run reached, once each (its visits
            folded), in the order first played.
        max_deviation_mm, max_deviation_at_s: the largest distance between the measured tool
            and the forward kinematics of the targets in force (the command stream), and when.
        trail_time_s, trail_position_m: the tool's path, about every 50 ms (and the last
            frame), m; at most :data:`~motiontool.sim.arm.TRAIL_POINTS` samples (every 100 ms,
            200 ms, ... in a longer run).
    """

    frame: str
    kind: str
    reach_tolerance_mm: float
    keyframes: tuple[KeyframePose, ...]
    max_deviation_mm: float
    max_deviation_at_s: float
    trail_time_s: tuple[float, ...]
    trail_position_m: tuple[tuple[float, float, float], ...]

    def to_json(self) -> dict[str, Any]:
        doc = asdict(self)
        doc["keyframes"] = [asdict(k) for k in self.keyframes]
        out: dict[str, Any] = _lists(doc)
        return out

    @classmethod
    def from_json(cls, doc: dict[str, Any]) -> EndEffectorStats:
        keyframes = tuple(_make(KeyframePose, _tuples(k)) for k in doc.get("keyframes") or [])
        values = _tuples({k: v for k, v in doc.items() if k != "keyframes"})
        values["keyframes"] = keyframes
        return _make(cls, values)

    def at(self, name: str) -> list[KeyframePose]:
        """The keyframes named ``name`` (several when poses or motions share the name)."""
        return [k for k in self.keyframes if k.name == name]


@dataclass
class PlayReport:
    """Everything ``play`` measured (see the module docstring for the JSON form)."""

    robot: str
    files: list[FileRun]
    options: dict[str, Any]
    stamps: dict[str, Any]
    simulated_s: float
    control_steps: int
    joints: list[JointStats]
    base: BaseStats | None
    feet: list[FootStats]
    self_collisions: list[ContactSummary]
    scene_contacts: list[ContactSummary]
    ground_contacts: list[ContactSummary]
    warnings: dict[str, int]
    ignored_joints: list[str] = field(default_factory=list)
    error: str | None = None
    unplayed_files: list[str] = field(default_factory=list)
    expectations: list[ExpectationResult] = field(default_factory=list)
    end_effector: EndEffectorStats | None = None
    physics: dict[str, Any] = field(default_factory=dict)
    world: dict[str, Any] | None = None
    self_collision: dict[str, Any] | None = None

    @property
    def problems(self) -> list[str]:
        """Why the run is not clean, one short phrase each (empty when clean)."""
        out = []
        if self.error:
            out.append(self.error)
        for path in self.unplayed_files:  # every column ignored: the run tested nothing
            what = "this motion" if len(self.files) <= 1 else f"{PurePath(path).name}"
            out.append(f"no joint of {what} is a motor of {self.robot}: nothing was played")
        raised = {k: v for k, v in self.warnings.items() if v}
        if raised:
            out.append(
                "MuJoCo warning " + ", ".join(f"{k} x{v}" for k, v in sorted(raised.items()))
            )
        fall_decided = any(r.expectation.decides_fall for r in self.expectations)
        if self.base is not None:
            if self.base.fell and fall_decided:
                pass  # an expectation says whether it should fall
            elif self.base.fell:
                out.append(f"fell at {self.base.fell_at_s:.2f} s")
            elif self.base.started_down and not self.base.upright_at_end:
                out.append("started down and did not get up")
        for c in self.self_collisions:
            out.append(f"self-collision {c.body_a}/{c.body_b} at {c.first_s:.2f} s")
        for c in self.scene_contacts:
            out.append(f"{c.body_a} touched {c.body_b} at {c.first_s:.2f} s")
        out += [r.reason for r in self.expectations if not r.passed]
        return out

    @property
    def clean(self) -> bool:
        """No error, no warning, no fall, no collision, every expectation met."""
        return not self.problems

    @property
    def exit_code(self) -> int:
        """0 clean, 1 fell / collided / simulator warning, 2 the run could not complete."""
        if self.error:
            return exit_codes.ERROR
        return exit_codes.CLEAN if self.clean else exit_codes.FINDINGS

    def to_json(self) -> dict[str, Any]:
        """The JSON document (a dict of JSON types; non-finite numbers become null)."""
        doc: dict[str, Any] = {
            "schema": SCHEMA,
            "schema_version": SCHEMA_VERSION,
            "stamps": dict(self.stamps),
            "robot": self.robot,
            "files": [asdict(f) for f in self.files],
            "options": dict(self.options),
            "physics": dict(self.physics),
            "world": self.world,
            "self_collision": self.self_collision,
            "simulated_s": self.simulated_s,
            "control_steps": self.control_steps,
            "clean": self.clean,
            "exit_code": self.exit_code,
            "reason": "; ".join(self.problems),
            "error": self.error,
            "base": asdict(self.base) if self.base is not None else None,
            "end_effector": self.end_effector.to_json() if self.end_effector else None,
            "joints": [asdict(j) for j in self.joints],
            "feet": [asdict(f) for f in self.feet],
            "self_collisions": [asdict(c) for c in self.self_collisions],
            "scene_contacts": [asdict(c) for c in self.scene_contacts],
            "ground_contacts": [asdict(c) for c in self.ground_contacts],
            "warnings": dict(self.warnings),
            "ignored_joints": list(self.ignored_joints),
            "unplayed_files": list(self.unplayed_files),
            "expectations": [r.to_json() for r in self.expectations],
        }
        out: dict[str, Any] = _finite(doc)
        return out

    @classmethod
    def from_json(cls, doc: dict[str, Any]) -> PlayReport:
        """The report of a JSON document written by :meth:`to_json` (its ``expectations`` are
        not read back: judge them again with :func:`motiontool.sim.expect.evaluate`)."""
        base = doc.get("base")
        ee = doc.get("end_effector")
        return cls(
            robot=doc["robot"],
            files=[_make(FileRun, f) for f in doc["files"]],
            options=dict(doc.get("options") or {}),
            physics=dict(doc.get("physics") or {}),
            world=doc.get("world"),
            self_collision=doc.get("self_collision"),
            stamps=dict(doc.get("stamps") or {}),
            simulated_s=doc["simulated_s"],
            control_steps=doc["control_steps"],
            joints=[_make(JointStats, j) for j in doc["joints"]],
            base=_make(BaseStats, base) if base is not None else None,
            feet=[_make(FootStats, f) for f in doc["feet"]],
            self_collisions=[_make(ContactSummary, c) for c in doc["self_collisions"]],
            scene_contacts=[_make(ContactSummary, c) for c in doc["scene_contacts"]],
            ground_contacts=[_make(ContactSummary, c) for c in doc["ground_contacts"]],
            warnings=dict(doc.get("warnings") or {}),
            ignored_joints=list(doc.get("ignored_joints") or []),
            error=doc.get("error"),
            unplayed_files=list(doc.get("unplayed_files") or []),
            end_effector=EndEffectorStats.from_json(ee) if ee else None,
        )


def _make(cls: type[_T], values: dict[str, Any]) -> _T:
    """``cls(**values)`` with the keys ``cls`` has (a newer report may carry more)."""
    names = {f.name for f in fields(cls)}  # type: ignore[arg-type]
    return cls(**{k: v for k, v in values.items() if k in names})


def _lists(value: Any) -> Any:
    """Tuples as lists, all the way down (JSON arrays)."""
    if isinstance(value, dict):
        return {k: _lists(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_lists(v) for v in value]
    return value


def _tuples(value: Any) -> Any:
    """Lists as tuples, all the way down (frozen dataclass fields)."""
    if isinstance(value, dict):
        return {k: _tuples(v) for k, v in value.items()}
    if isinstance(value, list):
        return tuple(_tuples(v) for v in value)
    return value


def _finite(value: Any) -> Any:
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_finite(v) for v in value]
    return value
