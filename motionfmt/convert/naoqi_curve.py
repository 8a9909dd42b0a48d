"""How NAOqi's ``ALMotion.angleInterpolationBezier`` moves a joint between two keys, as its
documentation describes it: a cubic Bézier curve in (time, angle) from one key to the next,
whose two inner control points are the keys' handles, each ``[type, dTime, dAngle]`` relative
to its key (the first handle of a key shapes the curve before it, the second the curve after).

This is the model that :mod:`.naoqi` writes keys for and measures its deviation with; what
the robot's motion module does with the keys is NAOqi's (no robot here to check it).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["BEZIER_HANDLE", "Key", "curve_at"]

BEZIER_HANDLE = 3
"""The handle type of Choregraphe's Bézier exports (``[3, dTime, dAngle]``)."""

#: A key: angle (rad), then handle 1 and handle 2, each [type, dTime (s), dAngle (rad)].
Key = tuple[float, tuple[int, float, float], tuple[int, float, float]]

_BISECTIONS = 60
"""Halvings of the curve parameter that find the point at a time: 2**-60 of a segment."""

_TIMES = 1 << 16
"""Times evaluated at once (the bisection's arrays are of this size, whatever the motion's
length)."""


def curve_at(
    times_s: list[float], keys: list[Key], at_s: npt.NDArray[np.float64]
) -> npt.NDArray[np.float64]:
    """The angle (rad) the curves through ``keys`` at ``times_s`` (s, increasing) give at each
    time of ``at_s`` (s), float64; NaN before the first key, the last key's angle after it."""
    import numpy as np

    t = np.asarray(times_s, dtype=np.float64)
    q = np.array([k[0] for k in keys], dtype=np.float64)
    h1 = np.array([k[1][1:] for k in keys], dtype=np.float64).reshape(-1, 2)
    h2 = np.array([k[2][1:] for k in keys], dtype=np.float64).reshape(-1, 2)
    out = np.full(at_s.shape, np.nan)
    out[at_s >= t[-1]] = q[-1]
    inside = np.nonzero((at_s >= t[0]) & (at_s < t[-1]))[0]
    for lo in range(0, inside.shape[0], _TIMES):  # each time alone: the same in blocks
        where = inside[lo : lo + _TIMES]
        x = at_s[where]
        a = np.searchsorted(t, x, side="right") - 1  # segment a -> a + 1
        p0t, p3t = t[a], t[a + 1]
        p1t, p2t = p0t + h2[a, 0], p3t + h1[a + 1, 0]
        p0q, p3q = q[a], q[a + 1]
        p1q, p2q = p0q + h2[a, 1], p3q + h1[a + 1, 1]
        lo_u, hi_u = np.zeros(x.shape), np.ones(x.shape)
        for _ in range(_BISECTIONS):  # t(u) increases: the handles stay inside their segment
            u = (lo_u + hi_u) / 2.0
            below = _cubic(p0t, p1t, p2t, p3t, u) < x
            lo_u, hi_u = np.where(below, u, lo_u), np.where(below, hi_u, u)
        out[where] = _cubic(p0q, p1q, p2q, p3q, (lo_u + hi_u) / 2.0)
    return out


def _cubic(
    p0: npt.NDArray[np.float64],
    p1: npt.NDArray[np.float64],
    p2: npt.NDArray[np.float64],
    p3: npt.NDArray[np.float64],
    u: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]:
    v = 1.0 - u
    return v * v * v * p0 + 3.0 * v * v * u * p1 + 3.0 * v * u * u * p2 + u * u * u * p3
