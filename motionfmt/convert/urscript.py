"""URScript (a real UR arm): a program that sends Webots' exact command stream with ``servoj``
at the control step, or one ``movej`` per keyframe.

The program first moves to the first pose slowly (``movej``, :data:`HOME_SPEED_RAD_S`,
:data:`HOME_ACCEL_RAD_S2`), wherever the arm stands. Then, by default, one ``servoj`` per
control step with the six targets Webots' player holds at that step (:mod:`.held`), ``t`` the
step: the numbers are Webots' own, written in the shortest positional decimal that reads back
to the same double (``repr``'s digits, never an exponent, which URScript may not read).
``lookahead_time`` and ``gain`` are UR's defaults (0.1 s, 300): how the arm tracks the targets
is UR's servo controller. With ``blend_rad_s2`` (a real arm, whose joint acceleration is
bounded) the corners of Webots' straight lines are rounded with parabolic blends at that
acceleration (:mod:`.blend`): every keyframe keeps its time, the lines between the blends are
Webots' own numbers, and the header says how far the blends pass from the keyframes.

With ``keyframes``: one ``movej`` per keyframe, ``t`` the segment's duration and blend radius
``r = 0`` (the arm reaches, and stops at, every keyframe: UR's joint profile between them, not
Webots' straight lines; no deviation is claimed).

The program ends by calling its ``def``, so that it runs as it is pasted or sent (to the
controller's port 30002, say), not only once something calls it.

Every one of the arm's joints (``ExportOptions.joint_order``, the robot's motor order) needs a
target from the first step on: ``servoj`` sets all six.
"""

from __future__ import annotations

import io
import itertools
import re
from collections.abc import Callable, Iterable, Iterator
from typing import TYPE_CHECKING

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
from motiontool.motionfmt.convert.blend import Blends, blended_chunks, plan_blends
from motiontool.motionfmt.convert.held import held_chunks
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.player import hold_targets
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = [
    "HOME_ACCEL_RAD_S2",
    "HOME_SPEED_RAD_S",
    "SERVO_GAIN",
    "SERVO_LOOKAHEAD_S",
    "number",
    "write_urscript",
]

HOME_SPEED_RAD_S = 0.2
"""Joint speed of the move to the first pose, rad/s: slow, from wherever the arm stands."""
HOME_ACCEL_RAD_S2 = 0.5
"""Joint acceleration of the move to the first pose, rad/s²."""
SERVO_LOOKAHEAD_S = 0.1
"""``servoj``'s lookahead_time, s (UR's default)."""
SERVO_GAIN = 300
"""``servoj``'s gain (UR's default)."""


def number(x: float) -> str:
    """``x`` in the shortest digits that read back to the same double, positional (no
    exponent): ``1e-05`` -> ``0.00001``."""
    import numpy as np

    return np.format_float_positional(x, unique=True, trim="0")


def _vector(row: npt.NDArray[np.float64]) -> str:
    return "[" + ", ".join(number(float(v)) for v in row) + "]"


def _columns(motors: tuple[str, ...], order: tuple[str, ...]) -> list[int]:
    extra = [m for m in motors if m not in order]
    if extra:
        raise MotionToolError(
            f"not a joint of the arm: {', '.join(extra)} (its joints: {', '.join(order)})"
        )
    missing = [j for j in order if j not in motors]
    if missing:
        raise MotionToolError(
            f"the motion has no column for {', '.join(missing)}: URScript sets every joint of "
            "the arm at once"
        )
    return [motors.index(j) for j in order]


def _first_command(
    order: tuple[str, ...], first: npt.NDArray[np.float64], arm: Callable[[], Iterator[StreamChunk]]
) -> None:
    """Raise where a joint of the arm has no target in the first row ``first`` (N,), saying
    from when it has one (``arm`` makes the stream again to find that out)."""
    import numpy as np

    unset = np.isnan(first)
    if not unset.any():
        return
    k = int(np.argmax(unset))
    since = "ever"
    for elapsed, targets in arm():
        live = np.flatnonzero(~np.isnan(targets[:, k]))
        if live.size:
            since = f"before {int(elapsed[live[0]])} ms"
            break
    raise MotionToolError(
        f"{order[k]} has no target {since} ('*'): URScript sets "
        "every joint at once; give it a number in the first pose"
    )


def _blend_note(blends: Blends, motion: Motion) -> list[str]:
    """The header's lines on the blended corners: how many, at what acceleration, and the
    largest deviation from the motion."""
    rad, pose, joint = blends.worst()
    name = motion.pose_names[pose]
    return [
        f"# its corners rounded with parabolic blends at {blends.accel_rad_s2:g} rad/s^2 "
        f"({blends.corners} corners; every keyframe at its time)",
        f"# largest deviation from the motion: {rad:.6g} rad ({blends.joints[joint]} at pose "
        f"{pose} '{name}', {int(motion.times_ms[pose])} ms)",
    ]


def _program(
    options: ExportOptions,
    order: tuple[str, ...],
    first: str,
    body: Iterable[str],
    note: Iterable[str] = (),
) -> bytes:
    """The program around ``body`` (its lines, each read once: a generator may make them as
    they are written); ``note``: more comment lines after the mode's."""
    mode = (
        "one movej per keyframe (t = its segment, r = 0: the arm stops at every keyframe)"
        if options.keyframes
        else f"servoj every {options.timestep_ms} ms: Webots' command stream"
    )
    head = [
        f"# motiontool convert: {options.source} for {options.robot or 'a UR arm'}",
        f"# {mode}",
        *note,
        f"# joint targets in rad, in the order {', '.join(order)}",
        f"# robot check: {robot_check(options)}",
        "def motiontool_motion():",
        f"  # to the first pose, slowly ({HOME_SPEED_RAD_S} rad/s, {HOME_ACCEL_RAD_S2} rad/s^2)",
        f"  movej({first}, a={HOME_ACCEL_RAD_S2}, v={HOME_SPEED_RAD_S})",
    ]
    out = io.BytesIO()
    tail = ["  stopj(2.0)", "end", "motiontool_motion()"]  # runs as pasted, or sent as a file
    for line in itertools.chain(head, body, tail):
        out.write(line.encode("utf-8", "surrogateescape"))
        out.write(b"\n")
    return out.getvalue()


def write_urscript(motion: Motion, options: ExportOptions) -> Exported:
    """The URScript program (see the module); raises :class:`MotionToolError` where an arm
    joint has no column or no target from the start. Webots' stream is made a chunk of steps
    at a time (for the program, again for the robot check), never held whole."""
    import numpy as np

    order = options.joint_order
    if order is None:
        raise MotionToolError("URScript needs the arm's joints in its order: name the robot")
    if options.keyframes:
        return _keyframes(motion, options, order)
    motors, chunks = held_chunks(motion, options.timestep_ms)
    columns = _columns(motors, order)

    def webots() -> Iterator[StreamChunk]:
        for elapsed, targets in chunks():
            yield elapsed, targets[:, columns]

    first = next(webots())[1][0]
    _first_command(order, first, webots)
    blends = None
    if options.blend_rad_s2 is not None:
        held = hold_targets(motion.values, motion.commanded, motion.joints, motors)
        targets, sent = held.targets[:, columns], held.sent[:, columns]
        blends = plan_blends(order, motion.times_ms, targets, sent, options.blend_rad_s2)

    def sent_and_webots() -> Iterator[tuple[StreamChunk, npt.NDArray[np.float64]]]:
        """(what is sent, Webots' targets at the same steps), a chunk at a time."""
        if blends is None:
            for elapsed, targets in webots():
                yield (elapsed, targets), targets
        else:
            for elapsed, base, blended in blended_chunks(webots(), blends, options.timestep_ms):
                yield (elapsed, blended), base

    def arm() -> Iterator[StreamChunk]:
        for chunk, _ in sent_and_webots():
            yield chunk

    t = number(options.timestep_ms / MS_PER_S)
    tail = f"t={t}, lookahead_time={number(SERVO_LOOKAHEAD_S)}, gain={SERVO_GAIN})"
    worst, rows = WorstError(), 0

    def body() -> Iterator[str]:
        nonlocal rows
        for (elapsed, targets), base in sent_and_webots():
            yield from _servoj(elapsed, targets, base, tail, worst, rows)
            rows += targets.shape[0]

    note = [] if blends is None else _blend_note(blends, motion)
    data = _program(options, order, _vector(first), body(), note)
    compared = "servoj targets as written, against Webots' stream at every step"
    if blends is not None:
        compared += " (the arm at rest before and after it)"
    deviation = Deviation(
        worst.rad, order[worst.column], worst.at_ms, f"{rows * len(order)} {compared}"
    )
    empty = np.zeros(0, dtype=np.int64)
    stream = RobotStream(order, empty, np.zeros((0, len(order))), arm)
    detail = f"servoj every {options.timestep_ms} ms, after a movej to the first pose"
    return Exported(data, rows, detail, deviation, stream=stream, blends=blends)


_SERVOJ = re.compile(r"servoj\(\[([^\]]*)\]")

_ROWS = 8192
"""servoj lines made (and read back) at a time: a long motion's lines are never all held."""


def _servoj(
    elapsed: npt.NDArray[np.int64],
    targets: npt.NDArray[np.float64],
    webots: npt.NDArray[np.float64],
    tail: str,
    worst: WorstError,
    first_row: int,
) -> Iterator[str]:
    """A servoj line per row of ``targets`` (rows from ``first_row`` on in the stream, sent
    at ``elapsed`` ms), :data:`_ROWS` at a time, each block read back and compared with
    ``webots`` (Webots' targets at the same steps) into ``worst``."""
    import numpy as np

    for lo in range(0, targets.shape[0], _ROWS):
        block = targets[lo : lo + _ROWS]
        lines = [f"  servoj({_vector(row)}, {tail}" for row in block]
        written = np.array([[float(x) for x in _SERVOJ.findall(ln)[0].split(",")] for ln in lines])
        error = np.abs(written - webots[lo : lo + _ROWS])
        worst.update(error, first_row + lo, elapsed[lo : lo + _ROWS])
        yield from lines


def _keyframes(motion: Motion, options: ExportOptions, order: tuple[str, ...]) -> Exported:
    refuse_non_finite(motion)
    motors = tuple(dict.fromkeys(motion.joints))
    held = hold_targets(motion.values, motion.commanded, motion.joints, motors).targets
    targets = held[:, _columns(motors, order)]
    _first_command(order, targets[0], lambda: iter([(motion.times_ms, targets)]))
    body = []
    for i in range(1, motion.n_poses):
        seconds = number(int(motion.times_ms[i] - motion.times_ms[i - 1]) / MS_PER_S)
        body.append(f"  movej({_vector(targets[i])}, t={seconds}, r=0)")
    data = _program(options, order, _vector(targets[0]), body)
    stream = RobotStream(order, motion.times_ms, targets)
    detail = "one movej per keyframe (t = the segment, blend r = 0), after a movej to the first"
    return Exported(data, motion.n_poses, detail, stream=stream)
