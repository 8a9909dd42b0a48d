"""Plane geometry of the support polygon: a convex hull and the signed distance to it (m)."""

from __future__ import annotations

import math
from collections.abc import Sequence

__all__ = ["convex_hull", "signed_distance"]


def _cross(o: Sequence[float], a: Sequence[float], b: Sequence[float]) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def convex_hull(points: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """Counter-clockwise convex hull (Andrew's monotone chain); collinear points dropped."""
    pts = sorted(set(points))
    if len(pts) <= 2:
        return pts
    lower: list[tuple[float, float]] = []
    for p in pts:
        while len(lower) >= 2 and _cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[tuple[float, float]] = []
    for p in reversed(pts):
        while len(upper) >= 2 and _cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def _segment_distance(
    p: tuple[float, float], a: tuple[float, float], b: tuple[float, float]
) -> float:
    ax, ay = b[0] - a[0], b[1] - a[1]
    length2 = ax * ax + ay * ay
    t = (
        0.0
        if length2 == 0
        else max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / length2))
    )
    return math.hypot(p[0] - (a[0] + t * ax), p[1] - (a[1] + t * ay))


def signed_distance(p: tuple[float, float], hull: Sequence[tuple[float, float]]) -> float:
    """Distance (m) from ``p`` to the hull's boundary: positive inside, negative outside."""
    if len(hull) == 1:
        return -math.hypot(p[0] - hull[0][0], p[1] - hull[0][1])
    edges = list(zip(hull, [*hull[1:], hull[0]], strict=True))
    distance = min(_segment_distance(p, a, b) for a, b in edges)
    if len(hull) >= 3 and all(_cross(a, b, p) >= 0 for a, b in edges):
        return distance
    return -distance
