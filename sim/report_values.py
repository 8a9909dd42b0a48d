"""The values of a play report that an expectation compares: one :data:`Measure` per quantity
of :data:`motiontool.sim.quantities.QUANTITIES`, in the quantity's unit, with a note (where it
was measured: ``at pick_1 (2.07 s)``), or None with the reason it could not be measured (a fixed
base has no base motion, no keyframe of that name was reached, ...).

Stdlib only: the report is read as :class:`motiontool.sim.report.PlayReport` holds it.
"""

from __future__ import annotations

import bisect
import difflib
import math
from collections.abc import Callable
from typing import TYPE_CHECKING

from motiontool.motionfmt.units import MM_PER_M

if TYPE_CHECKING:
    from motiontool.sim.expect_syntax import Expectation
    from motiontool.sim.report import KeyframePose, PlayReport

__all__ = [
    "Measure",
    "base_value",
    "count",
    "ee_deviation",
    "ee_error",
    "ee_lag",
    "ee_position",
    "fall_direction",
    "feet",
    "heading",
    "joint_value",
]

Measure = Callable[["PlayReport", "Expectation | None"], tuple["float | None", str]]
"""A value of the report, in the quantity's unit, and a note ('' or where it was measured:
'at pick_1 (2.07 s)'); or None with the reason it was not measured."""


def base_value(key: str) -> Measure:
    """The base statistic ``key`` of the report (``dx_m``, ``yaw_change_deg``, ...), in its unit."""

    def measure(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
        if report.base is None:
            return None, f"{report.robot} has a fixed base: no base motion"
        value = getattr(report.base, key)
        if value is None:
            why = {
                "yaw_change_deg": "the robot was never upright",
                "fell_at_s": "it did not fall",
                "fall_direction_deg": "it did not fall",
            }.get(key, "no value")
            return None, why
        return float(value), ""

    return measure


def fall_direction(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
    """Which way the robot fell, deg from its heading before the fall (0 forward, 90 left)."""
    measured, why = base_value("fall_direction_deg")(report, e)
    if measured is None and report.base is not None and report.base.fell:
        return None, "the report does not say which way (made before fall_direction existed)"
    return measured, why


def heading(axis: int) -> Measure:
    """The root displacement along the start heading (``axis`` 0) or to its left (1), m."""

    def measure(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
        if report.base is None:
            return None, f"{report.robot} has a fixed base: no base motion"
        yaw = math.radians(float(report.options.get("start_yaw_deg") or 0.0))
        dx, dy = report.base.dx_m, report.base.dy_m
        along = dx * math.cos(yaw) + dy * math.sin(yaw)
        left = -dx * math.sin(yaw) + dy * math.cos(yaw)
        return (along if axis == 0 else left), ""

    return measure


def feet(key: str) -> Measure:
    """The largest foot statistic ``key`` (``slip_m``, ``max_displacement_m``) over the feet, mm."""

    def measure(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
        if not report.feet:
            return None, f"{report.robot} has no feet"
        return max(float(getattr(f, key)) for f in report.feet) * MM_PER_M, ""

    return measure


def joint_value(key: str) -> Measure:
    """The joint statistic ``key`` of the expectation's joint, else the worst commanded joint."""

    def measure(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
        joint = e.joint if e is not None else None
        if joint is not None:
            names = [j.name for j in report.joints]
            for j in report.joints:
                if j.name == joint:
                    value = getattr(j, key)
                    return (None, "not finite") if value is None else (float(value), "")
            close = difflib.get_close_matches(joint, names, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            return None, f"{report.robot} has no joint '{joint}'{hint}"
        values = [getattr(j, key) for j in report.joints if j.commanded]
        if not values:
            return None, "no joint was commanded"
        if any(v is None for v in values):
            return None, "not finite"
        return max(float(v) for v in values), ""

    return measure


def count(key: str) -> Measure:
    """How many entries the report list ``key`` holds (``self_collisions``, ...)."""

    def measure(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
        return float(len(getattr(report, key))), ""

    return measure


def _no_tool(report: PlayReport) -> str:
    if report.base is not None:
        return f"{report.robot} has a free-flying base: no end effector is measured"
    return f"{report.robot}: no end effector was measured"


def _keyframes(report: PlayReport, e: Expectation | None) -> tuple[list[KeyframePose], str]:
    """The keyframes an expectation names (all of them when it names none), or [] and why."""
    ee = report.end_effector
    if ee is None:
        return [], _no_tool(report)
    name = e.keyframe if e is not None else None
    if name is None:
        return (list(ee.keyframes), "") if ee.keyframes else ([], "no keyframe was reached")
    found = ee.at(name)
    if found:
        return found, ""
    names = list(dict.fromkeys(k.name for k in ee.keyframes))
    close = difflib.get_close_matches(name, names, n=1)
    hint = f"; did you mean '{close[0]}'?" if close else ""
    return [], f"no keyframe named '{name}' was reached{hint}"


def _where(k: KeyframePose) -> str:
    """A keyframe entry in words; a folded one says how many visits it holds."""
    many = f", worst of {k.visits} visits" if k.visits > 1 else ""
    return f"at {k.name} ({k.time_s:.2f} s){many}"


def ee_error(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
    """The tool's largest distance (mm) from a keyframe's forward kinematics at its time."""
    found, why = _keyframes(report, e)
    if not found:
        return None, why
    worst = max(found, key=lambda k: k.position_error_mm)
    return float(worst.position_error_mm), _where(worst)


def ee_lag(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
    """The longest time (ms) after a keyframe until the tool is within the reach tolerance."""
    found, why = _keyframes(report, e)
    if not found:
        return None, why
    assert report.end_effector is not None
    lags = [(k.lag_ms, k) for k in found]
    never = [k for lag, k in lags if lag is None]
    if never:
        k = never[0]
        tol = report.end_effector.reach_tolerance_mm
        if k.visits > 1:
            return None, (
                f"the tool never came within {tol:g} mm of {k.name} at one of its {k.visits} "
                f"visits before the motion moved on (error at the keyframe time up to "
                f"{k.position_error_mm:.1f} mm)"
            )
        return None, (
            f"the tool never came within {tol:g} mm of {k.name} ({k.time_s:.2f} s) before the "
            f"motion moved on (closest at the keyframe time: {k.position_error_mm:.1f} mm)"
        )
    lag, worst = max(((lag, k) for lag, k in lags if lag is not None), key=lambda p: p[0])
    return lag, _where(worst)


def ee_deviation(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
    """The tool's largest distance (mm) from the forward kinematics of the commands."""
    ee = report.end_effector
    if ee is None:
        return None, _no_tool(report)
    return float(ee.max_deviation_mm), f"at {ee.max_deviation_at_s:.2f} s"


def ee_position(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
    """Distance (m) from the expectation's point to the tool at its keyframe or time."""
    if e is None or e.point is None:
        return None, "no point given"
    ee = report.end_effector
    if ee is None:
        return None, _no_tool(report)
    points: list[tuple[tuple[float, float, float], str]] = []
    if e.at_s is not None:
        times, trail = ee.trail_time_s, ee.trail_position_m
        if not times or not times[0] <= e.at_s <= times[-1]:
            end = times[-1] if times else 0.0
            return None, f"{e.at_s:g} s is outside the run (0 to {end:.2f} s)"
        i = max(1, bisect.bisect_left(times, e.at_s))
        i = min(i, len(times) - 1)
        t0, t1 = times[i - 1], times[i]
        w = 0.0 if t1 == t0 else (e.at_s - t0) / (t1 - t0)
        p = tuple(a + w * (b - a) for a, b in zip(trail[i - 1], trail[i], strict=True))
        points.append(((p[0], p[1], p[2]), f"at {e.at_s:g} s"))
    else:
        found, why = _keyframes(report, e)
        if not found:
            return None, why
        points += [(k.farthest_from(e.point), _where(k)) for k in found]
    distances = [(math.dist(p, e.point), p, where) for p, where in points]
    distance, p, where = max(distances)
    shown = ", ".join(f"{v:.4f}" for v in p)
    return distance, f"[{shown}] m {where}, {distance * MM_PER_M:.1f} mm away"
