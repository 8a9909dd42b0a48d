"""Measuring a run: the trace of a simulation (:class:`motiontool.sim.trace.Trace`) made into the
numbers of its :class:`motiontool.sim.report.PlayReport`: the base (displacement, heading, tilt,
the fall and which way), the feet, each joint's tracking and time at its caps, and the contacts.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.units import MM_PER_M, MS_PER_S
from motiontool.sim.report import (
    BaseStats,
    ContactSummary,
    FileRun,
    FootStats,
    JointStats,
    PlayReport,
)

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.sim._mujoco import Scene
    from motiontool.sim.play_options import PlayOptions
    from motiontool.sim.trace import ContactEvent, Trace

__all__ = [
    "LIMIT_TOLERANCE",
    "RECOVERY_MARGIN_DEG",
    "RECOVERY_MARGIN_M",
    "TORQUE_CAP_FRACTION",
    "DownFrames",
    "RunMeter",
    "counted_contacts",
    "tilt_and_heading",
]

TORQUE_CAP_FRACTION = 0.999
"""A motor counts as torque-limited when its torque reaches this fraction of maxTorque."""

LIMIT_TOLERANCE = 0.01
"""How far past a motor limit (rad, or m) a position must be to count as beyond the limits."""


def tilt_and_heading(quat: npt.NDArray[np.float64]) -> tuple[Any, Any]:
    """(tilt, heading) in degrees of (N, 4) quaternions (w, x, y, z)."""
    import numpy as np

    w, x, y, z = quat.T
    r22 = np.clip(1.0 - 2.0 * (x * x + y * y), -1.0, 1.0)
    r00 = 1.0 - 2.0 * (y * y + z * z)
    r10 = 2.0 * (x * y + w * z)
    return np.degrees(np.arccos(r22)), np.degrees(np.arctan2(r10, r00))


RECOVERY_MARGIN_M = 0.01
"""How far above ``fall_height_m`` (m) a root that is down must rise to be up again."""

RECOVERY_MARGIN_DEG = 5.0
"""How far below ``fall_tilt_deg`` (degrees) a root that is down must straighten to be up again."""


class DownFrames:
    """Where the robot is down, a chunk at a time (:meth:`frames` each chunk in order), with
    hysteresis: a robot that is up goes down when its root is lower than ``fall_height_m`` or
    tilted more than ``fall_tilt_deg``; a robot that is down is up again only once its root is
    :data:`RECOVERY_MARGIN_M` above that height and :data:`RECOVERY_MARGIN_DEG` below that tilt.
    Between the two it keeps its state, so a root that rests at the threshold (a kneel whose
    torso sits at 0.2 m, within the millimetres its contacts settle by) is not read as getting
    up and falling again. The run's first frame is down only when it is low or tilted."""

    def __init__(self, opts: PlayOptions) -> None:
        self.opts = opts
        self.last: bool | None = None  # the state at the last frame so far

    def frames(self, trace: Trace, new: int) -> npt.NDArray[np.bool_]:
        """(N,) bool: the frames of ``trace`` where the robot is down; its frames before
        ``new`` are the last of the chunk before (their state is kept)."""
        import numpy as np

        tilt, _heading = tilt_and_heading(trace.base_quat)
        height, opts = trace.base_pos[:, 2], self.opts
        low = (height < opts.fall_height_m) | (tilt > opts.fall_tilt_deg)
        high = (height >= opts.fall_height_m + RECOVERY_MARGIN_M) & (
            tilt <= opts.fall_tilt_deg - RECOVERY_MARGIN_DEG
        )
        state = low.copy()
        decided = low | high
        if new and self.last is not None:
            state[:new], decided[:new] = self.last, True
        decided[0] = True  # the run's first frame: down only when low or tilted
        latest = np.maximum.accumulate(np.where(decided, np.arange(len(state)), 0))
        down: npt.NDArray[np.bool_] = state[latest]
        self.last = bool(down[-1])
        return down


def _fall_direction_deg(quat: npt.NDArray[np.float64], heading_deg: float) -> float:
    """Which way a root with orientation ``quat`` (w, x, y, z) leans, in degrees from
    ``heading_deg`` (the heading it had while up), in (-180, 180]: 0 forward, 90 left, -90
    right, 180 back (the horizontal direction of its z axis)."""
    w, x, y, z = (float(v) for v in quat)
    lean = math.degrees(math.atan2(2.0 * (y * z - w * x), 2.0 * (x * z + w * y)))
    turned = (lean - heading_deg + 180.0) % 360.0 - 180.0
    return 180.0 if turned == -180.0 else turned


class _BaseMeter:
    """The root body: displacement, heading, tilt, the fall and which way (:class:`BaseStats`)."""

    def __init__(self, opts: PlayOptions) -> None:
        self.opts = opts
        self.start: npt.NDArray[np.float64] | None = None
        self.started_down = False
        self.max_tilt: Any = None
        self.min_height: Any = None
        self.yaw: Any = None  # the heading change over the frames up, deg: a running sum
        self.last_up_heading: Any = None  # the heading at the last frame up so far
        self.fell_at: float | None = None
        self.direction: float | None = None
        self.end: tuple[npt.NDArray[np.float64], float, bool] | None = None
        self.downs = DownFrames(opts)

    def add(self, trace: Trace, new: int) -> None:
        """Measure the frames of ``trace`` from its frame ``new`` on (those before were
        measured with the chunk before)."""
        import numpy as np

        tilt, heading = tilt_and_heading(trace.base_quat)
        down = self.downs.frames(trace, new)
        if self.start is None:
            self.start, self.started_down = trace.base_pos[0].copy(), bool(down[0])
        height = trace.base_pos[new:, 2]
        self.max_tilt = _fold(np.maximum, self.max_tilt, tilt[new:].max())
        self.min_height = _fold(np.minimum, self.min_height, height.min())
        up = np.flatnonzero(~down[new:]) + new
        if len(up):
            headings = heading[up]
            if self.last_up_heading is not None:
                headings = np.concatenate(([self.last_up_heading], headings))
            if self.fell_at is None:
                self._fall(trace, down, heading, new if self.last_up_heading is not None else up[0])
            steps = np.diff(headings)
            self.yaw = _fold(np.add, self.yaw, np.sum((steps + 180.0) % 360.0 - 180.0))
            self.last_up_heading = heading[up[-1]]
        elif self.fell_at is None and self.last_up_heading is not None:
            self._fall(trace, down, heading, new)
        self.end = (trace.base_pos[-1].copy(), float(tilt[-1]), bool(down[-1]))

    def _fall(self, trace: Trace, down: Any, heading: Any, after: int) -> None:
        """The first frame down from frame ``after`` of the chunk on, which was up before."""
        import numpy as np

        later = np.flatnonzero(down[after:])
        if len(later):
            k = int(after + later[0])  # the first frame down; k - 1 was up
            self.fell_at = float(trace.time_s[k])
            self.direction = _fall_direction_deg(trace.base_quat[k], float(heading[k - 1]))

    def stats(self) -> BaseStats:
        assert self.start is not None and self.end is not None
        end, final_tilt, down_at_end = self.end
        d = end - self.start
        return BaseStats(
            dx_m=float(d[0]),
            dy_m=float(d[1]),
            dz_m=float(d[2]),
            yaw_change_deg=None if self.yaw is None else float(self.yaw),
            max_tilt_deg=float(self.max_tilt),
            final_tilt_deg=final_tilt,
            min_height_m=float(self.min_height),
            final_height_m=float(end[2]),
            started_down=self.started_down,
            fell=self.fell_at is not None,
            fell_at_s=self.fell_at,
            upright_at_end=not down_at_end,
            fall_direction_deg=self.direction,
        )


def _fold(op: Any, total: Any, part: Any) -> Any:
    """``op(total, part)``, or ``part`` for the first part (NaN propagates, as in numpy)."""
    return part if total is None else op(total, part)


class _FeetMeter:
    """Each foot: time in contact, slip, displacement (:class:`FootStats`)."""

    def __init__(self) -> None:
        self.start: npt.NDArray[np.float64] | None = None
        self.contact: Any = 0
        self.slip: Any = 0.0  # each foot's, a running sum
        self.max_away: Any = None
        self.final_away: Any = None

    def add(self, trace: Trace, new: int) -> None:
        import numpy as np

        xy = trace.foot_pos[:, :, :2]
        touching = trace.foot_contact
        if self.start is None:
            self.start = xy[0].copy()
        self.contact = self.contact + touching[1:].sum(axis=0)
        moves = np.linalg.norm(np.diff(xy, axis=0), axis=2)
        both = touching[1:] & touching[:-1]
        self.slip = self.slip + np.array([moves[both[:, f], f].sum() for f in range(xy.shape[1])])
        away = np.linalg.norm(xy - self.start, axis=2)
        self.max_away = _fold(np.maximum, self.max_away, away[new:].max(axis=0))
        self.final_away = away[-1]

    def stats(self, feet: Sequence[str], step_ms: int) -> list[FootStats]:
        return [
            FootStats(
                name=name,
                contact_s=_seconds(self.contact[f], step_ms),
                slip_m=float(self.slip[f]),
                max_displacement_m=float(self.max_away[f]),
                final_displacement_m=float(self.final_away[f]),
            )
            for f, name in enumerate(feet)
        ]


class _JointMeter:
    """Each motor: tracking error from its first command on, time at its caps
    (:class:`JointStats`)."""

    def __init__(self, scene: Scene) -> None:
        import numpy as np

        n = len(scene.joints)
        self.scene = scene
        self.counts = np.zeros((4, n), dtype=np.int64)  # velocity cap, torque cap, clip, beyond
        self.ever = np.zeros(n, dtype=np.bool_)
        # (sum of squared errors, steps, largest |error|): from the joint's first command on,
        # over every step while it has none (what a joint never commanded reports)
        self.error: list[tuple[Any, int, Any]] = [(0.0, 0, None)] * n

    def add(self, trace: Trace) -> None:
        import numpy as np

        lim = self.scene.limits
        clipped = np.clip(trace.targets, lim.lower, lim.upper)
        error = clipped - trace.position[1:]
        pos = trace.position[1:]
        self.counts += np.stack(
            [
                np.abs(trace.velocity_cmd) >= lim.max_velocity,
                np.abs(trace.torque) >= TORQUE_CAP_FRACTION * lim.max_torque,
                (trace.targets < lim.lower) | (trace.targets > lim.upper),
                (pos < lim.lower - LIMIT_TOLERANCE) | (pos > lim.upper + LIMIT_TOLERANCE),
            ]
        ).sum(axis=1)
        sent: npt.NDArray[np.bool_] = np.asarray(trace.commanded.any(axis=0))
        first = trace.commanded.argmax(axis=0)
        for j in range(len(self.ever)):
            e = error[:, j]
            if sent[j] and not self.ever[j]:  # its first command: the steps before do not count
                self.ever[j] = True
                self.error[j] = (0.0, 0, None)
                e = error[first[j] :, j]
            if len(e):
                total, steps, worst = self.error[j]
                self.error[j] = (
                    total + np.sum(e * e),
                    steps + len(e),
                    _fold(np.maximum, worst, np.abs(e).max()),
                )

    def stats(self, step_ms: int) -> list[JointStats]:
        import numpy as np

        out = []
        scene = self.scene
        for j, name in enumerate(scene.joints):
            total, steps, worst = self.error[j]
            velocity, torque, clipped, beyond = (int(c) for c in self.counts[:, j])
            out.append(
                JointStats(
                    name=name,
                    limb=scene.joint_limbs[j],
                    unit=scene.robot.joint(name).unit,
                    commanded=bool(self.ever[j]),
                    rms_error=float(np.sqrt(total / steps)) if steps else 0.0,
                    max_error=float(worst) if steps else 0.0,
                    velocity_cap_s=_seconds(velocity, step_ms),
                    torque_cap_s=_seconds(torque, step_ms),
                    target_clipped_s=_seconds(clipped, step_ms),
                    beyond_limits_s=_seconds(beyond, step_ms),
                )
            )
        return out


def counted_contacts(
    trace: Trace,
    kind: str,
    opts: PlayOptions,
    *,
    touches: Callable[[str, str], bool] | None = None,
) -> list[ContactEvent]:
    """The events of ``kind``; self-collisions: the probe's from the tolerance down, and the
    contacts between robot bodies that the simulation itself collides which ``touches``
    counts (:meth:`Scene.touch_counts`; None: every one)."""
    if kind != "self":
        return [e for e in trace.events if e.kind == kind]
    floor = opts.collision_tolerance_mm / MM_PER_M
    return [
        e
        for e in trace.events
        if (e.kind == "touch" and (touches is None or touches(e.body_a, e.body_b)))
        or (e.kind == "self" and e.depth_m >= floor)
    ]


class _ContactMeter:
    """One summary per pair of bodies and kind of contact: first frame, frames seen (as a
    duration), deepest (:class:`ContactSummary`)."""

    def __init__(self, opts: PlayOptions, touches: Callable[[str, str], bool]) -> None:
        self.opts, self.touches = opts, touches
        self.pairs: dict[str, dict[tuple[str, str], list[Any]]] = {
            k: {} for k in (*CONTACT_KINDS, "touch")
        }

    def add(self, trace: Trace) -> None:
        for kind, pairs in self.pairs.items():
            for e in counted_contacts(trace, kind, self.opts, touches=self.touches):
                seen = pairs.get((e.body_a, e.body_b))
                if seen is None:
                    pairs[(e.body_a, e.body_b)] = [e.frame, e.frame, 1, max(0.0, e.depth_m)]
                    continue
                if e.frame != seen[1]:  # events come in frame order
                    seen[1] = e.frame
                    seen[2] += 1
                seen[3] = max(seen[3], e.depth_m)

    def summaries(self, kind: str, step_ms: int) -> list[ContactSummary]:
        pairs = self.pairs[kind]
        return [
            ContactSummary(
                key[0],
                key[1],
                _seconds(pairs[key][0], step_ms),
                _seconds(pairs[key][2], step_ms),
                pairs[key][3],
            )
            for key in sorted(pairs, key=lambda k: (pairs[k][0], k))
        ]


CONTACT_KINDS = ("self", "scene", "ground")
"""The kinds of counted contacts the report summarises (:func:`counted_contacts`)."""


class RunMeter:
    """Measures a run a chunk at a time (:func:`motiontool.sim._mujoco.run_chunks`): feed it
    every chunk in order (:meth:`add`), then make the report (:meth:`report`). Nothing of a
    chunk is kept: memory is flat whatever the run's duration. One chunk or many give the
    same report, sums of many terms (a root mean square, the yaw, the slip) to rounding."""

    def __init__(self, scene: Scene, opts: PlayOptions) -> None:
        self.scene, self.opts = scene, opts
        self._joints = _JointMeter(scene)
        self._base = _BaseMeter(opts) if scene.floating else None
        self._feet = _FeetMeter()
        self._contacts = _ContactMeter(opts, scene.touch_counts)
        self._last: Trace | None = None

    def add(self, chunk: Trace) -> None:
        """Measure the next chunk of the run."""
        new = 0 if self._last is None else 1  # its frame 0 is the last frame of the one before
        self._joints.add(chunk)
        if self._base is not None:
            self._base.add(chunk, new)
        self._feet.add(chunk, new)
        self._contacts.add(chunk)
        self._last = chunk

    def self_contacts(self) -> list[ContactSummary]:
        """The pairs of robot bodies that touched in the simulation itself (self-collision
        physics), as far as measured."""
        last = self._last
        return [] if last is None else self._contacts.summaries("touch", last.control_step_ms)

    @property
    def control_steps(self) -> int:
        """The control steps measured so far."""
        last = self._last
        return 0 if last is None else last.first_frame + last.steps_done

    def report(
        self,
        files: list[FileRun],
        options_doc: dict[str, Any],
        stamps: dict[str, Any],
        ignored: list[str],
    ) -> PlayReport:
        """The report of the run: its ``files``, ``options`` and ``stamps`` as given, the
        joints, base, feet and contacts measured, the columns ``ignored`` (no motor of the
        robot), the simulator's warnings and error."""
        last = self._last
        assert last is not None, "a run has at least one chunk"
        step_ms = last.control_step_ms
        return PlayReport(
            robot=self.scene.robot.name,
            files=files,
            options=options_doc,
            stamps=stamps,
            simulated_s=float(last.time_s[-1]),
            control_steps=self.control_steps,
            joints=self._joints.stats(step_ms),
            base=None if self._base is None else self._base.stats(),
            feet=self._feet.stats(last.feet, step_ms),
            self_collisions=self._contacts.summaries("self", step_ms),
            scene_contacts=self._contacts.summaries("scene", step_ms),
            ground_contacts=self._contacts.summaries("ground", step_ms),
            warnings=dict(last.warnings),
            ignored_joints=ignored,
            error=last.error,
        )


def _seconds(steps: Any, step_ms: int) -> float:
    """``steps`` control steps (or a frame index) of ``step_ms`` ms, in s: whole ms, then s,
    rounded once (201 steps of 20 ms are 4.02 s; 201 * 0.02 is 4.0200000000000005)."""
    return int(steps) * step_ms / MS_PER_S
