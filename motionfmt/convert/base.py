"""What every format of :mod:`motiontool.motionfmt.convert` is made of: how it reads a file into
a :class:`~motiontool.motionfmt.motion.Motion` (:class:`Imported`), how it writes one
(:class:`Exported`, with :class:`ExportOptions`), and its row in the registry (:class:`Format`).

Pure: robot knowledge (the motor order of an arm, its name for a comment) comes in as plain
data in :class:`ExportOptions`; the robot checks of an export are the caller's.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.motionfmt.player import WEBOTS_DEFAULT_TIMESTEP_MS

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.convert.blend import Blends
    from motiontool.motionfmt.motion import Motion
    from motiontool.motionfmt.reader import ReadResult

__all__ = [
    "DEFAULT_JOINT_STATE_TOPIC",
    "DEFAULT_LEAD_IN_MS",
    "DEFAULT_MAX_ERROR_RAD",
    "UNCHECKED",
    "Deviation",
    "ExportOptions",
    "Exported",
    "Format",
    "ImportOptions",
    "Imported",
    "Recording",
    "RobotStream",
    "Sampled",
    "StreamChunk",
    "WorstError",
    "robot_check",
]

DEFAULT_LEAD_IN_MS = 1000
"""Milliseconds a real robot gets to reach the first pose from wherever it stands, before the
motion starts (NAOqi's first time must be > 0; Webots jumps to the first pose at 0 ms)."""

UNCHECKED = "unchecked"
"""What a written file says of its robot check where none ran (``--robot none``, or no robot
detected for a data format)."""

DEFAULT_JOINT_STATE_TOPIC = "/joint_states"
"""The ``sensor_msgs/JointState`` topic a ROS 2 bag is read from and written to by default (a
real robot's, as ``joint_state_broadcaster`` publishes it)."""

DEFAULT_MAX_ERROR_RAD = 1e-3
"""How far (rad, m for linear joints) the keyframes of an imported recording may stray from
its samples when they are reduced (0.057 degrees: far below what a motion shows, far above
the noise of an arm's encoders)."""


@dataclass(frozen=True)
class ExportOptions:
    """What a writer needs besides the motion.

    Attributes:
        timestep_ms: the controller time step, ms: the command stream that is reproduced is
            Webots' at this step.
        source: the input, as the user named it (for comments and metadata).
        robot: the robot the export was checked against (its name, for comments and
            metadata), or None: unchecked, which a format with a place for it says
            (:func:`robot_check`).
        joint_order: the robot's motors in its own order (a UR arm's six joints), or None.
        coupled_joints: the robot's (leader, follower) pairs that one motor drives on the real
            robot (``nao-v5``'s two HipYawPitch), from its robot facts: NAOqi names the
            follower by its leader.
        lead_in_ms: time to reach the first pose before the motion starts, ms (NAOqi).
        keyframes: one move per keyframe instead of the stream at every step (URScript).
        target_name: the output file as its companion script opens it: its path from the
            script's folder (its name, beside it), or None where it is no file (standard
            output, a device: the script is told where the file is).
        script_name: the companion script's file name, or None: the format's own, beside the
            output (NAOqi: ``wave_send.py`` for ``wave.naoqi.json``).
        joint_map: (motion's joint, the robot's ROS name) pairs for the joints whose names
            differ (ROS formats); the others keep their name.
        topic: the ``sensor_msgs/JointState`` topic of a ROS 2 bag.
        blend_rad_s2: round the corners of Webots' lines with parabolic blends at this joint
            acceleration, rad/s² (URScript's servoj stream for a real arm); None: send them
            as they are.
    """

    timestep_ms: int = WEBOTS_DEFAULT_TIMESTEP_MS
    source: str = "<motion>"
    robot: str | None = None
    joint_order: tuple[str, ...] | None = None
    coupled_joints: tuple[tuple[str, str], ...] = ()
    lead_in_ms: int = DEFAULT_LEAD_IN_MS
    keyframes: bool = False
    target_name: str | None = None
    script_name: str | None = None
    joint_map: tuple[tuple[str, str], ...] = ()
    topic: str = DEFAULT_JOINT_STATE_TOPIC
    blend_rad_s2: float | None = None


def robot_check(options: ExportOptions) -> str:
    """What a file says of its robot check, in a field or comment of its own (NAOqi's
    ``robot_check``, a YAML or URScript comment, an NPZ array, a bag's metadata): the robot's
    name, or :data:`UNCHECKED`. CSV and ``.motion`` have no place their readers skip."""
    return options.robot or UNCHECKED


@dataclass(frozen=True)
class ImportOptions:
    """What a reader needs besides the file (a recording's; the data formats need nothing).

    Attributes:
        topic: the ``sensor_msgs/JointState`` topic to read from a ROS 2 bag.
        joint_map: (motion's joint, ROS name) pairs, as :attr:`ExportOptions.joint_map`: a
            recorded ROS name becomes the motion's joint.
        max_error_rad: how far the reduced keyframes may stray from the recording, rad (m for
            linear joints); 0 keeps every sample that is not exactly on a line.
        timestep_ms: the control step a keyframe animation (Choregraphe's curves) is sampled
            at, ms: the robot's.
    """

    topic: str = DEFAULT_JOINT_STATE_TOPIC
    joint_map: tuple[tuple[str, str], ...] = ()
    max_error_rad: float = DEFAULT_MAX_ERROR_RAD
    timestep_ms: int = WEBOTS_DEFAULT_TIMESTEP_MS


@dataclass(frozen=True)
class Deviation:
    """The worst difference between what the exported file makes the robot do (as modelled)
    and Webots' command stream.

    Attributes:
        max_rad: the largest |difference|, rad (m for linear joints); 0.0 when identical.
        joint: where it is largest (None when nothing was compared).
        at_ms: its playback time in Webots' stream, ms (None when nothing was compared).
        compared: how many targets were compared, and at which times (for a report).
    """

    max_rad: float
    joint: str | None
    at_ms: int | None
    compared: str


class WorstError:
    """The largest entry of an (S, N) array of errors (rad; finite) seen a block of rows at a
    time, and where: the first in row order, as ``argmax`` of the whole array finds it; its
    row, column and time (``at_ms``: ms of Webots' playback time, where the blocks say)."""

    def __init__(self) -> None:
        self.rad, self.row, self.column = 0.0, 0, 0
        self.at_ms: int | None = None
        self._seen = False

    def update(
        self,
        err: npt.NDArray[np.float64],
        first_row: int,
        times_ms: npt.NDArray[np.int64] | None = None,
    ) -> None:
        """Take the errors ``err`` (rows, N) of the rows from ``first_row`` on, sent at the
        times ``times_ms`` (rows,), ms."""
        import numpy as np

        if err.size == 0:
            return
        k = np.unravel_index(int(np.argmax(err)), err.shape)
        if err[k] > self.rad or not self._seen:
            self.rad, self.row, self.column = float(err[k]), first_row + int(k[0]), int(k[1])
            self.at_ms = None if times_ms is None else int(times_ms[k[0]])
            self._seen = True


StreamChunk = tuple["npt.NDArray[np.int64]", "npt.NDArray[np.float64]"]
"""(times_ms int64 (S,), targets float64 (S, N)) of a part of a stream of targets, in its
order: a :class:`RobotStream`'s, or the held stream of :func:`.held.held_chunks`."""


@dataclass(frozen=True)
class RobotStream:
    """The targets an export sends to the robot, for the robot checks before it is written:
    held whole, or made a chunk of rows at a time as they are checked.

    Attributes:
        joints: the N motors.
        times_ms: int64 (S,): when each row is sent, ms of Webots' playback time (empty where
            ``made`` gives the rows).
        targets: float64 (S, N), rad (m for linear joints); NaN where nothing is sent.
        made: None, or what makes the rows a chunk at a time, in time order, each time it is
            called (a long stream is never held whole).
    """

    joints: tuple[str, ...]
    times_ms: npt.NDArray[np.int64]
    targets: npt.NDArray[np.float64]
    made: Callable[[], Iterator[StreamChunk]] | None = None

    def chunks(self) -> Iterator[StreamChunk]:
        """The rows as (times_ms (S,), targets (S, N)) chunks, in time order."""
        if self.made is None:
            yield self.times_ms, self.targets
        else:
            yield from self.made()


@dataclass(frozen=True)
class Exported:
    """A written file, and what it holds.

    Attributes:
        data: the file's bytes.
        poses: how many poses (rows, keyframes or commands) it holds.
        detail: what they are, for ``wrote X (N poses, DETAIL)``.
        deviation: how far it is from Webots' stream (None for a lossless format).
        companions: (suffix, bytes) of files written beside it (a script that sends it).
        stream: what it sends to the robot, for the robot checks (None for a data format).
        blends: the corners it rounds (URScript's servoj stream for a real arm), or None.
    """

    data: bytes
    poses: int
    detail: str
    deviation: Deviation | None = None
    companions: tuple[tuple[str, bytes], ...] = ()
    stream: RobotStream | None = None
    blends: Blends | None = None


@dataclass(frozen=True)
class Recording:
    """What an imported recording held, and how far the motion made of it is from it.

    Attributes:
        topic: the topic read.
        messages: how many messages it held.
        duration_ms: from the first stamp to the last, ms.
        merged: samples left out because an earlier one falls on the same whole ms.
        max_error_rad: the bound the keyframes were reduced within, rad.
        deviation: the motion (straight lines between its keyframes) against every recorded
            sample at its own stamp, rad.
        reduced_rad: the bound the keyframes were reduced within, rad: ``max_error_rad``, or
            less where rounding the times to whole ms put the motion beyond it.
        notes: what else the reader did, one line each (joints merged from several
            publishers, unstamped messages placed at their log time).
        heading: what was read, the report's first line, where it is no topic's messages (a
            trajectory's points); None: ``messages`` of ``topic``.
        against: what the motion is compared against, for the report.
    """

    topic: str
    messages: int
    duration_ms: int
    merged: int
    max_error_rad: float
    deviation: Deviation
    reduced_rad: float
    notes: tuple[str, ...] = ()
    heading: str | None = None
    against: str = "the recording"

    def within(self) -> bool:
        """Whether the motion keeps within ``max_error_rad`` of every sample, with 1e-9 rad of
        slack for float rounding (as validate's checks allow on positions)."""
        return self.deviation.max_rad <= self.max_error_rad + 1e-9


@dataclass(frozen=True)
class Sampled:
    """What an imported animation of curves (Choregraphe's keys) held, and how far the motion
    made of it is from its curves.

    Attributes:
        what: the file's kind, for a report (``a Choregraphe timeline at 25 fps``).
        keys: how many keys it held, of ``curves`` joints.
        curves: how many joint curves.
        start_s: the time of its earliest key, s: the motion's 0 ms (what comes before it is the
            robot reaching the first keys from its posture, not the animation).
        step_ms: the control step the curves were sampled at, ms.
        samples: how many times each curve was sampled at.
        max_error_rad: the bound the keyframes were reduced within, rad.
        deviation: the motion (straight lines between its keyframes) against the curves at
            every sampled time, rad.
        notes: what the reading assumed, one line each.
    """

    what: str
    keys: int
    curves: int
    start_s: float
    step_ms: int
    samples: int
    max_error_rad: float
    deviation: Deviation
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class Imported:
    """A motion read from a file.

    Attributes:
        motion: the motion.
        path: the file, as diagnostics name it.
        read: the :class:`~motiontool.motionfmt.reader.ReadResult` of a ``.motion`` file (its
            diagnostics point at its own cells), else None.
        cells: (line, column) of each value cell, int64 (P, J, 2), 1-based, where the format
            has lines (CSV); None otherwise.
        header: the 1-based column of each joint's name on line 1, int64 (J,), with ``cells``.
        recording: for a recording (a ROS 2 bag), what it held and the motion's deviation
            from it; None otherwise.
        sampled: for an animation of curves (Choregraphe), what it held and the motion's
            deviation from its curves; None otherwise.
    """

    motion: Motion
    path: str
    read: ReadResult | None = None
    cells: npt.NDArray[np.int64] | None = None
    header: npt.NDArray[np.int64] | None = None
    recording: Recording | None = None
    sampled: Sampled | None = None


@dataclass(frozen=True)
class Format:
    """One row of the registry: a format, what it is for, and what it can do.

    Attributes:
        name: what the user types (``csv``).
        suffixes: file name endings that select it (``.csv``), lower case.
        summary: one line, for the help.
        read: bytes, the file's name and :class:`ImportOptions` -> :class:`Imported`; None if
            it cannot be read.
        write: motion and options -> :class:`Exported`; None if it cannot be written.
        for_robot: whether the file drives a real robot (its export must pass the robot
            checks, warnings included) rather than hold data.
        default_robot: the robot it is for when none is named (``ur5e``), or None.
        read_folder: a folder's path and :class:`ImportOptions` -> :class:`Imported`, for a
            format kept as a folder (a ROS 2 bag's, with its ``metadata.yaml``); else None.
        uses: the fields of :class:`ImportOptions` / :class:`ExportOptions` it reads beyond
            the common ones (``topic``, ``joint_map``, ``max_error_rad``), so that a front end
            can refuse one given to a format that ignores it.
    """

    name: str
    suffixes: tuple[str, ...]
    summary: str
    read: Callable[[bytes, str, ImportOptions], Imported] | None = None
    write: Callable[[Motion, ExportOptions], Exported] | None = None
    for_robot: bool = False
    default_robot: str | None = None
    uses: frozenset[str] = frozenset()
    read_folder: Callable[[str, ImportOptions], Imported] | None = None
