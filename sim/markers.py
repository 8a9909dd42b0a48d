"""What happened during a run, for the recording's event log: each motion's start, the falls and
get-ups, the contacts as they begin, targets clipped at the limits and positions past them, and
the simulator's warnings and errors, as :class:`Marker` in time order."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from motiontool.sim.measure import LIMIT_TOLERANCE, DownFrames, counted_contacts

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.sim.motor import MotorLimits
    from motiontool.sim.play_options import PlayOptions
    from motiontool.sim.report import FileRun
    from motiontool.sim.trace import Trace

__all__ = ["Marker", "MarkerMeter"]


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


def _starts(flags: npt.NDArray[np.bool_], before: Any = False) -> npt.NDArray[np.intp]:
    """Indices where a boolean series turns true (``before``: the value before its first)."""
    import numpy as np

    prev = np.concatenate([np.broadcast_to(before, flags[:1].shape), flags[:-1]])
    return np.flatnonzero(flags & ~prev)


_CONTACT_WORDS = {"self": "self-collision", "scene": "contact", "ground": "on the floor"}
"""How the recording's event log names each kind of counted contact."""


class MarkerMeter:
    """The events of a run, found a chunk at a time (:meth:`add` each chunk of
    :func:`motiontool.sim._mujoco.run_chunks` in order, then :meth:`markers`): only the
    events and what the last frame or step was are kept."""

    def __init__(
        self,
        limits: MotorLimits,
        opts: PlayOptions,
        *,
        floating: bool,
        touches: Callable[[str, str], bool] | None = None,
    ) -> None:
        self.limits, self.opts, self.floating = limits, opts, floating
        self.touches = touches  # Scene.touch_counts
        self._falls: tuple[list[Marker], list[Marker]] = ([], [])  # fell, upright
        self._downs = DownFrames(opts)
        self._contacts: dict[str, dict[tuple[str, str], list[Marker]]] = {
            k: {} for k in _CONTACT_WORDS
        }
        self._last_contact: dict[tuple[str, str, str], int] = {}
        self._limits: list[tuple[list[Marker], list[Marker]]] = []  # targets, positions
        self._last_target: Any = False  # each joint's target was outside at the last step
        self._last: Trace | None = None

    def add(self, chunk: Trace) -> None:
        """Find the events of the next chunk of the run."""
        new = 0 if self._last is None else 1  # its frame 0 is the last frame of the one before
        if self.floating:
            self._fall_markers(chunk, new)
        self._contact_markers(chunk)
        self._limit_markers(chunk, new)
        self._last = chunk

    def markers(self, files: Sequence[FileRun]) -> list[Marker]:
        """Events of the run for the recording's timeline, in time order: each motion's start,
        falls, contacts, limits, then the simulator's warnings and error."""
        last = self._last
        assert last is not None, "a run has at least one chunk"
        out = [Marker(f.start_s, "INFO", f"start {Path(f.path).name}", "motion") for f in files]
        out += self._falls[0] + self._falls[1]
        out += [m for pairs in self._contacts.values() for ms in pairs.values() for m in ms]
        out += [m for targets, positions in self._limits for m in targets + positions]
        t_end = float(last.time_s[-1])
        raised = {k: v for k, v in last.warnings.items() if v}
        if raised:
            out.append(Marker(t_end, "ERROR", f"MuJoCo warnings: {raised}", "simulator"))
        if last.error:
            out.append(Marker(t_end, "ERROR", last.error, "simulator"))
        out.sort(key=lambda m: m.time_s)
        return out

    def _fall_markers(self, trace: Trace, new: int) -> None:
        """Where the robot goes down and gets up again (not at the start)."""
        t = trace.time_s
        down = self._downs.frames(trace, new)
        # the frame before this chunk's new ones (none at the run's start: neither down nor up)
        down_before = new == 1 and bool(down[0])
        up_before = new == 1 and not down[0]
        fell, upright = self._falls
        for k in (_starts(down[new:], down_before) + new).tolist():
            if trace.first_frame + k:
                fell.append(Marker(float(t[k]), "ERROR", "fell (root low or tilted)", "fall"))
        for k in (_starts(~down[new:], up_before) + new).tolist():
            if trace.first_frame + k:
                upright.append(Marker(float(t[k]), "INFO", "upright", "fall"))

    def _contact_markers(self, trace: Trace) -> None:
        """Where each pair of bodies starts touching, for each counted kind of contact (events
        come in frame order)."""
        for kind, pairs in self._contacts.items():
            level = "INFO" if kind == "ground" else "WARN"
            for e in counted_contacts(trace, kind, self.opts, touches=self.touches):
                key = (kind, e.body_a, e.body_b)
                last = self._last_contact.get(key)
                if last == e.frame:
                    continue
                self._last_contact[key] = e.frame
                started = pairs.setdefault((e.body_a, e.body_b), [])
                if last is None or last != e.frame - 1:
                    text = f"{_CONTACT_WORDS[kind]}: {e.body_a} / {e.body_b}"
                    time_s = float(trace.time_s[e.frame - trace.first_frame])
                    started.append(Marker(time_s, level, text, "collision"))

    def _limit_markers(self, trace: Trace, new: int) -> None:
        """Where a target starts to lie outside the limits (it is clipped), and where a
        position starts to lie past them by more than :data:`LIMIT_TOLERANCE`."""
        lim, t = self.limits, trace.time_s
        if not self._limits:
            self._limits = [([], []) for _ in trace.joints]
        outside = (trace.targets < lim.lower) | (trace.targets > lim.upper)
        pos = trace.position
        beyond = (pos < lim.lower - LIMIT_TOLERANCE) | (pos > lim.upper + LIMIT_TOLERANCE)
        for j, name in enumerate(trace.joints):
            lower, upper = lim.lower[j], lim.upper[j]
            target = trace.targets[:, j]
            clipped, past = self._limits[j]
            before = False if new == 0 else bool(self._last_target[j])
            for k in _starts(outside[:, j], before).tolist():
                text = f"{name} target {target[k]:.4g} outside [{lower:.4g}, {upper:.4g}]: clipped"
                clipped.append(Marker(float(t[k]), "WARN", text, "limit"))
            for k in (
                _starts(beyond[new:, j], bool(beyond[0, j]) if new else False) + new
            ).tolist():
                text = f"{name} at {pos[k, j]:.4g}, past its limits"
                past.append(Marker(float(t[k]), "WARN", text, "limit"))
        if len(outside):
            self._last_target = outside[-1]
