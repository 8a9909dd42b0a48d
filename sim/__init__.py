"""Simulation: play motions headlessly in MuJoCo as Webots would, record runs to Rerun, batch runs.

Importing this package is cheap: MuJoCo (:mod:`motiontool.sim._mujoco`) and Rerun
(:mod:`motiontool.sim.recording`) are imported only when a run or a recording needs them.

May import ``motionfmt``, ``kinematics`` and the top-level modules; MuJoCo only in
:mod:`._mujoco`, Rerun in :mod:`.recording`, Ray in :mod:`._ray`; never ``cli``.
"""

from motiontool.sim.expect import (
    Expectation,
    ExpectationError,
    ExpectationResult,
    evaluate,
    parse_expectation,
)
from motiontool.sim.motor import DEFAULT_P_GAIN, MotorLimits, velocity_command
from motiontool.sim.play import (
    LIMIT_TOLERANCE,
    TORQUE_CAP_FRACTION,
    Marker,
    PlayOptions,
    command_matrix,
    command_stream,
    play,
    read_playable,
)
from motiontool.sim.report import (
    SCHEMA,
    SCHEMA_VERSION,
    BaseStats,
    ContactSummary,
    EndEffectorStats,
    FileRun,
    FootStats,
    JointStats,
    KeyframePose,
    PlayReport,
)
from motiontool.sim.start import LYING_STARTS, StartState
from motiontool.sim.trace import BodyShapes, ContactEvent, Shape, Trace

__all__ = [
    "DEFAULT_P_GAIN",
    "LIMIT_TOLERANCE",
    "LYING_STARTS",
    "SCHEMA",
    "SCHEMA_VERSION",
    "TORQUE_CAP_FRACTION",
    "BaseStats",
    "BodyShapes",
    "ContactEvent",
    "ContactSummary",
    "EndEffectorStats",
    "Expectation",
    "ExpectationError",
    "ExpectationResult",
    "FileRun",
    "FootStats",
    "JointStats",
    "KeyframePose",
    "Marker",
    "MotorLimits",
    "PlayOptions",
    "PlayReport",
    "Shape",
    "StartState",
    "Trace",
    "command_matrix",
    "command_stream",
    "evaluate",
    "parse_expectation",
    "play",
    "read_playable",
    "velocity_command",
]
