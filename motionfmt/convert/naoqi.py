"""NAOqi (a real NAO): the arguments of ``ALMotion.angleInterpolationBezier`` as JSON, and a
small Python script that sends them with ``qi``.

What it reproduces: the targets each motor holds while Webots plays the motion at the control
step (:mod:`.held`): straight lines between the poses, nothing sent across a ``*`` stretch (the
motor holds its last target, then jumps). NAOqi's plain ``angleInterpolation`` smooths between
keys in a way its documentation does not give; ``angleInterpolationBezier`` takes the curve
between two keys as a cubic Bézier with the keys' handles as its inner control points
(:mod:`.naoqi_curve`). Handles placed on the straight line to the neighbouring key make each
segment exactly that line, so the keys are the corners of Webots' stream at the control step
(``*`` cells dropped per joint; a jump after a ``*`` stretch is two keys one step apart) and
the model of NAOqi's curve gives Webots' targets back to rounding: the deviation each export
reports is that model evaluated at every step against :func:`~motiontool.motionfmt.sample`.

Times: NAOqi wants every time > 0, and a real robot must first get to the first pose from
wherever it stands (Webots jumps there at 0 ms). Every NAOqi time is Webots' playback time
plus a lead-in (:data:`~.base.DEFAULT_LEAD_IN_MS`): the robot moves from its posture to the
first key in the lead-in, then plays the motion as Webots does.

Names: the real robot's hand is one joint (``LHand``, ``RHand``, 0 closed to 1 open, as the
simulated phalanges) and one motor drives both HipYawPitch joints; Webots' ``LPhalanx1..8``
become ``LHand`` (``RPhalanx1..8``: ``RHand``) and ``RHipYawPitch`` follows ``LHipYawPitch``
(the robot checks of nao-v5 require the coupled joints to agree).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionToolError
from motiontool.motionfmt.convert.base import (
    Deviation,
    Exported,
    ExportOptions,
    RobotStream,
    StreamChunk,
    WorstError,
    robot_check,
)
from motiontool.motionfmt.convert.held import Corners, held_chunks
from motiontool.motionfmt.convert.joint_map import NAO_HANDS
from motiontool.motionfmt.convert.naoqi_curve import BEZIER_HANDLE, Key, curve_at
from motiontool.motionfmt.convert.naoqi_script import SCRIPT_SUFFIX, script
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["BezierCurves", "bezier_curves", "naoqi_names", "write_naoqi"]


def naoqi_names(coupled_joints: Sequence[tuple[str, str]]) -> dict[str, str]:
    """Webots motor -> the NAOqi joint that moves it on the real robot (others keep their
    name): a follower of ``coupled_joints`` (the robot's (leader, follower) pairs one motor
    drives, ``nao-v5``'s ``RHipYawPitch`` after ``LHipYawPitch``) is its leader, and a hand's
    phalanges are its one joint (:data:`NAO_HANDS`)."""
    return {
        **{follower: NAO_HANDS.get(leader, leader) for leader, follower in coupled_joints},
        **NAO_HANDS,
    }


def _keys(t_s: npt.NDArray[np.float64], q: npt.NDArray[np.float64]) -> list[Key]:
    """Keys at times ``t_s`` (s) with angles ``q`` (rad), each handle a third of the way to
    its neighbour along the straight line (the first key's first handle flat, as Choregraphe
    writes it: the robot comes to rest there from its posture)."""
    keys: list[Key] = []
    n = t_s.shape[0]
    for i in range(n):
        t, a = float(t_s[i]), float(q[i])
        if i == 0:
            before = (BEZIER_HANDLE, -t / 3.0, 0.0)
        else:
            before = (BEZIER_HANDLE, (float(t_s[i - 1]) - t) / 3.0, (float(q[i - 1]) - a) / 3.0)
        if i == n - 1:
            after = (BEZIER_HANDLE, 0.0, 0.0)
        else:
            after = (BEZIER_HANDLE, (float(t_s[i + 1]) - t) / 3.0, (float(q[i + 1]) - a) / 3.0)
        keys.append((a, before, after))
    return keys


def _corners(
    motors: tuple[str, ...], chunks: Callable[[], Iterator[StreamChunk]], names: dict[str, str]
) -> tuple[dict[str, int], list[Corners]]:
    """The keys of every motor's held targets from its first command on (:class:`Corners`),
    and NAOqi name -> the motor that drives it (the first of the motion's motors that maps to
    it and is ever commanded)."""
    import numpy as np

    corners = [Corners() for _ in motors]
    for elapsed, targets in chunks():
        for k, found in enumerate(corners):
            live = ~np.isnan(targets[:, k])
            found.add(elapsed[live], targets[live, k])
    chosen: dict[str, int] = {}
    for k, motor in enumerate(motors):
        name = names.get(motor, motor)
        if name not in chosen and corners[k].count:
            chosen[name] = k
    return chosen, corners


def _model(
    curves: dict[str, tuple[list[float], list[Key]]], elapsed: npt.NDArray[np.int64], lead_in: int
) -> dict[str, npt.NDArray[np.float64]]:
    """What each NAOqi joint's curve gives at the steps ``elapsed`` (ms of Webots' playback
    time), rad."""
    import numpy as np

    t_s = (elapsed.astype(np.float64) + lead_in) / MS_PER_S
    return {name: curve_at(times, keys, t_s) for name, (times, keys) in curves.items()}


def _deviation(
    motors: tuple[str, ...],
    chunks: Callable[[], Iterator[StreamChunk]],
    curves: dict[str, tuple[list[float], list[Key]]],
    lead_in: int,
    names: dict[str, str],
) -> Deviation:
    """Worst |NAOqi model - Webots' held target| over every step where a motor holds one, the
    stream read a chunk at a time (per motor the first of its worst, then the motors in
    order)."""
    import numpy as np

    compared_motors = [k for k, m in enumerate(motors) if names.get(m, m) in curves]
    worst_by_motor = {k: WorstError() for k in compared_motors}  # each motor's first worst
    compared, row = 0, 0
    for elapsed, targets in chunks():
        model = _model(curves, elapsed, lead_in)
        for k in compared_motors:
            got, want = model[names.get(motors[k], motors[k])], targets[:, k]
            mask = ~np.isnan(want) & ~np.isnan(got)
            compared += int(mask.sum())
            err = np.where(mask, np.abs(got - want), 0.0)
            worst_by_motor[k].update(err[:, None], row, elapsed)
        row += elapsed.shape[0]
    worst, joint, at = 0.0, None, None
    for k, of_motor in worst_by_motor.items():  # the motors in order
        if of_motor.rad > worst or joint is None:
            worst, joint, at = of_motor.rad, motors[k], of_motor.at_ms
    what = f"{compared} targets, every control step of every motor from its first command on"
    return Deviation(worst, joint, at, what)


@dataclass(frozen=True)
class BezierCurves:
    """``angleInterpolationBezier``'s arguments for a motion, and what they make the robot do.

    Attributes:
        names: the NAOqi joints.
        times: each joint's key times, s (Webots' playback time plus the lead-in).
        keys: each joint's keys: angle (rad; a hand 0 to 1), handle before, handle after.
        deviation: NAOqi's curves (as modelled) against Webots' command stream.
        stream: what they send, for the robot checks.
    """

    names: list[str]
    times: list[list[float]]
    keys: list[list[Key]]
    deviation: Deviation
    stream: RobotStream

    @property
    def n_keys(self) -> int:
        """How many keys, of every joint."""
        return sum(len(t) for t in self.times)


def bezier_curves(motion: Motion, options: ExportOptions) -> BezierCurves:
    """The keys that reproduce Webots' command stream (see the module). Webots' stream is made
    a chunk of steps at a time, three times (the keys, the deviation, the stream for the robot
    checks): never held whole, whatever the motion's duration."""
    import numpy as np

    if options.lead_in_ms <= 0:
        raise MotionToolError(
            f"the lead-in must be > 0 ms (NAOqi times are), got {options.lead_in_ms}"
        )
    motors, chunks = held_chunks(motion, options.timestep_ms)
    renamed = naoqi_names(options.coupled_joints)
    columns, corners = _corners(motors, chunks, renamed)
    if not columns:
        raise MotionToolError("no joint of the motion is ever commanded: nothing to send")
    curves: dict[str, tuple[list[float], list[Key]]] = {}
    for name, k in columns.items():
        at_ms, values = corners[k].keys()
        t_s = (at_ms.astype(np.float64) + options.lead_in_ms) / MS_PER_S
        curves[name] = ([float(x) for x in t_s], _keys(t_s, values))
    names = list(curves)
    deviation = _deviation(motors, chunks, curves, options.lead_in_ms, renamed)

    def stream() -> Iterator[StreamChunk]:
        for elapsed, _targets in chunks():
            model = _model(curves, elapsed, options.lead_in_ms)
            yield elapsed, np.column_stack([model[name] for name in names])

    empty = np.zeros(0, dtype=np.int64)
    sent = RobotStream(
        tuple(motors[k] for k in columns.values()), empty, np.zeros((0, len(names))), stream
    )
    times, keys = [c[0] for c in curves.values()], [c[1] for c in curves.values()]
    return BezierCurves(names, times, keys, deviation, sent)


def write_naoqi(motion: Motion, options: ExportOptions) -> Exported:
    """The JSON of ``angleInterpolationBezier``'s arguments, with its script as a companion."""
    curves = bezier_curves(motion, options)
    doc = _document(options, curves.names, curves.times, curves.keys, curves.deviation)
    data = (json.dumps(doc, indent=1) + "\n").encode("utf-8", "surrogateescape")
    detail = (
        f"{curves.n_keys} keys of {len(curves.names)} NAOqi joints for "
        f"angleInterpolationBezier, times + {options.lead_in_ms} ms lead-in"
    )
    companion = (SCRIPT_SUFFIX, script(options.target_name, options.script_name).encode())
    return Exported(data, curves.n_keys, detail, curves.deviation, (companion,), curves.stream)


def _document(
    options: ExportOptions,
    names: list[str],
    times: list[list[float]],
    keys: list[list[Key]],
    deviation: Deviation,
) -> dict[str, Any]:
    return {
        "format": "motiontool.naoqi",
        "format_version": 1,
        "source": options.source,
        "robot": options.robot,
        "robot_check": robot_check(options),
        "call": "ALMotion.angleInterpolationBezier",
        "units": {"times": "s", "angles": "rad (LHand, RHand: 0 closed to 1 open)"},
        "timestep_ms": options.timestep_ms,
        "lead_in_ms": options.lead_in_ms,
        "worst_deviation_rad": deviation.max_rad,
        "names": names,
        "times": times,
        "keys": [[[a, list(h1), list(h2)] for a, h1, h2 in joint] for joint in keys],
    }
