"""The ``sensor_msgs/JointState`` messages of one topic made samples of every joint on common
times, as teams record them: one publisher naming every joint in each message, or several
(an arm's driver and a gripper's, say) each naming some.

Merged by joint name: each joint's own samples are its positions at the stamps of the
messages that name it (strictly increasing). The samples of the motion are at every stamp of
any message (each once), from the first stamp at which every joint has a sample to the last at
which every joint still has one (no joint is extrapolated); a joint is interpolated linearly
between its own samples at the stamps of the others. With one publisher this is every message
as it is. How far the motion is from the recording is measured against each joint's own
samples (:func:`joint_deviation`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.convert._ros import NS_PER_MS, JointStates
from motiontool.motionfmt.convert.base import Deviation

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["Merged", "joint_deviation", "merged"]


@dataclass(frozen=True)
class Merged:
    """Every joint's samples, and the common times they are put on.

    Attributes:
        names: the ROS names, in the order they first appear.
        start_ns: the first common stamp, ns: the motion's 0 ms.
        t_ms: float64 (M,): the common times, ms from ``start_ns``.
        q: float64 (M, J): every joint at them, rad (m).
        own: per joint, (its own times, ms from ``start_ns``; its own positions) inside the
            common span.
        publishers: how many different sets of names the messages give.
    """

    names: tuple[str, ...]
    start_ns: int
    t_ms: npt.NDArray[np.float64]
    q: npt.NDArray[np.float64]
    own: tuple[tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]], ...]
    publishers: int


def _seconds(ns: int) -> str:
    """``ns`` nanoseconds as seconds with all nine decimals, exactly."""
    return f"{'-' if ns < 0 else ''}{abs(ns) // 10**9}.{abs(ns) % 10**9:09d}"


def _series(states: JointStates, path: str, topic: str) -> dict[str, tuple[list[int], list[float]]]:
    """Each joint's (stamps ns, positions), in order of first appearance; raises at the first
    message that names no joint or one twice, whose positions do not match its names or are
    not finite, or that is not after the previous message naming the same joint."""
    import numpy as np

    if not states.names:
        raise MotionToolError(f"'{path}': topic {topic} holds no message")
    series: dict[str, tuple[list[int], list[float]]] = {}
    last: dict[str, int] = {}  # joint -> index of the last message naming it
    for i, (names, q) in enumerate(zip(states.names, states.positions, strict=True)):
        where = f"'{path}': {topic} message {i + 1}"
        if not names or len(set(names)) != len(names):
            raise MotionToolError(f"{where} names {list(names)}: no joint or one twice")
        if q.shape != (len(names),):
            raise MotionToolError(f"{where} has {q.shape[0]} positions for {len(names)} names")
        if not np.isfinite(q).all():
            k = int(np.argmax(~np.isfinite(q)))
            raise MotionToolError(f"{where}: {names[k]} = {float(q[k])!r} is not finite")
        ns = int(states.stamps_ns[i])
        for name, value in zip(names, q.tolist(), strict=True):
            stamps, values = series.setdefault(name, ([], []))
            if stamps and ns <= stamps[-1]:
                raise MotionToolError(
                    f"{where} is stamped {_seconds(ns)} s, not after message {last[name] + 1}'s "
                    f"{_seconds(stamps[-1])} s: header stamps must increase"
                )
            stamps.append(ns)
            values.append(value)
            last[name] = i
    return series


def merged(states: JointStates, path: str, topic: str) -> Merged:
    """The samples of every joint on common times (see the module).

    Raises:
        MotionToolError: a bad message (:func:`_series`), or joints never recorded at once.
    """
    import numpy as np

    series = _series(states, path, topic)
    firsts = {n: s[0][0] for n, s in series.items()}
    lasts = {n: s[0][-1] for n, s in series.items()}
    start, end = max(firsts.values()), min(lasts.values())
    if start > end:
        late = max(firsts, key=lambda n: firsts[n])
        early = min(lasts, key=lambda n: lasts[n])
        raise MotionToolError(
            f"'{path}': {topic} records {early} until {_seconds(end)} s and {late} only from "
            f"{_seconds(start)} s: no time has a sample of every joint"
        )
    every = np.unique(np.asarray(states.stamps_ns, dtype=np.int64))
    common = every[(every >= start) & (every <= end)]
    t_ms = (common - start) / NS_PER_MS
    columns, own = [], []
    for stamps, values in series.values():
        s_ms = (np.asarray(stamps, dtype=np.int64) - start) / NS_PER_MS
        v = np.asarray(values, dtype=np.float64)
        columns.append(np.interp(t_ms, s_ms, v))
        inside = (s_ms >= 0) & (s_ms <= t_ms[-1])
        own.append((s_ms[inside], v[inside]))
    publishers = len({frozenset(n) for n in states.names})
    q = np.stack(columns, axis=1)
    return Merged(tuple(series), start, t_ms, q, tuple(own), publishers)


def joint_deviation(
    motion: Motion, samples: Merged, columns: list[int], compared: str
) -> Deviation:
    """The motion's straight lines against each joint's own samples at their own stamps, rad;
    ``columns``: the motion's joints as columns of ``samples`` (a NAO's ``LHand`` gives eight)."""
    import numpy as np

    key_t = motion.times_ms.astype(np.float64)
    worst = Deviation(0.0, None, None, compared)
    for j, c in enumerate(columns):
        t, q = samples.own[c]
        if t.size == 0:
            continue
        err = np.abs(np.interp(t, key_t, motion.values[:, j]) - q)
        k = int(np.argmax(err))
        if worst.joint is None or err[k] > worst.max_rad:
            worst = Deviation(float(err[k]), motion.joints[j], round(float(t[k])), compared)
    return worst
