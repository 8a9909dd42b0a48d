"""What happened during a run, for the recording's event log: each motion's start, the falls and
get-ups, the contacts as they begin, targets clipped at the limits and positions past them, and
the simulator's warnings and errors, as :class:`Marker` in time order."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.sim.measure import LIMIT_TOLERANCE, SimulatedRun, counted_contacts, down_frames

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.sim.motor import MotorLimits
    from motiontool.sim.play_options import PlayOptions
    from motiontool.sim.report import PlayReport
    from motiontool.sim.trace import Trace

__all__ = ["Marker", "markers"]


@dataclass(frozen=True)
class Marker:
    """Something that happened during the run, for the recording's event log.

    Attributes:
        time_s: when, simulated s. level: ``INFO``, ``WARN`` or ``ERROR``. text: what.
        entity: which part of the recording it concerns (``fall``, ``collision``, ``limit``,
            ``motion``, ``simulator``).
    """

    time_s: float
    level: str
    text: str
    entity: str


def _starts(flags: npt.NDArray[np.bool_]) -> npt.NDArray[np.intp]:
    """Indices where a boolean series turns true."""
    import numpy as np

    prev = np.concatenate([[False], flags[:-1]])
    return np.flatnonzero(flags & ~prev)


def markers(run: SimulatedRun, report: PlayReport) -> list[Marker]:
    """Events of the run for the recording's timeline, in time order."""
    trace = run.trace
    out = [Marker(f.start_s, "INFO", f"start {Path(f.path).name}", "motion") for f in run.files]
    if report.base is not None:
        out += _fall_markers(trace, run.opts)
    out += _contact_markers(trace, run.opts)
    out += _limit_markers(trace, run.scene.limits)
    t_end = float(trace.time_s[-1])
    raised = {k: v for k, v in trace.warnings.items() if v}
    if raised:
        out.append(Marker(t_end, "ERROR", f"MuJoCo warnings: {raised}", "simulator"))
    if trace.error:
        out.append(Marker(t_end, "ERROR", trace.error, "simulator"))
    out.sort(key=lambda m: m.time_s)
    return out


def _fall_markers(trace: Trace, opts: PlayOptions) -> list[Marker]:
    """Where the robot goes down and gets up again (not at the start)."""
    t = trace.time_s
    down = down_frames(trace, opts)
    out = [
        Marker(float(t[k]), "ERROR", "fell (root low or tilted)", "fall")
        for k in _starts(down).tolist()
        if k
    ]
    out += [Marker(float(t[k]), "INFO", "upright", "fall") for k in _starts(~down).tolist() if k]
    return out


_CONTACT_WORDS = {"self": "self-collision", "scene": "contact", "ground": "on the floor"}
"""How the recording's event log names each kind of counted contact."""


def _contact_markers(trace: Trace, opts: PlayOptions) -> list[Marker]:
    """Where each pair of bodies starts touching, for each counted kind of contact."""
    import numpy as np

    t = trace.time_s
    frames: dict[tuple[str, str, str], list[int]] = {}
    for kind in _CONTACT_WORDS:
        for e in counted_contacts(trace, kind, opts):
            frames.setdefault((kind, e.body_a, e.body_b), []).append(e.frame)
    out = []
    for (kind, a, b), ks in frames.items():
        flags = np.zeros(len(t), dtype=bool)
        flags[ks] = True
        level = "INFO" if kind == "ground" else "WARN"
        text = f"{_CONTACT_WORDS[kind]}: {a} / {b}"
        out += [Marker(float(t[k]), level, text, "collision") for k in _starts(flags).tolist()]
    return out


def _limit_markers(trace: Trace, lim: MotorLimits) -> list[Marker]:
    """Where a target starts to lie outside the limits (it is clipped), and where a position
    starts to lie past them by more than :data:`LIMIT_TOLERANCE`."""
    t = trace.time_s
    out = []
    for j, name in enumerate(trace.joints):
        lower, upper = lim.lower[j], lim.upper[j]
        target = trace.targets[:, j]
        for k in _starts((target < lower) | (target > upper)).tolist():
            text = f"{name} target {target[k]:.4g} outside [{lower:.4g}, {upper:.4g}]: clipped"
            out.append(Marker(float(t[k]), "WARN", text, "limit"))
        pos = trace.position[:, j]
        beyond = (pos < lower - LIMIT_TOLERANCE) | (pos > upper + LIMIT_TOLERANCE)
        for k in _starts(beyond).tolist():
            text = f"{name} at {pos[k]:.4g}, past its limits"
            out.append(Marker(float(t[k]), "WARN", text, "limit"))
    return out
