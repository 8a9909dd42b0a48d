"""Behaviour expectations of a run: ``dx>=0.3``, ``yaw=60±10``, ``upright``, judged on a report.

A run is *clean* when the robot does not fall, nothing collides and the simulator raises no
warning; an expectation says what the motion must also *do*. Two forms:

- ``QUANTITY OP VALUE[UNIT]`` with OP one of ``<`` ``<=`` ``>`` ``>=`` ``=`` (``=`` needs a
  tolerance: ``±TOL[UNIT]``, also written ``+-TOL``, or ``±P%`` of the value; a unit after
  the tolerance alone applies to the value too: ``torso_height=33±1cm``), e.g.
  ``dx>=0.3``, ``yaw=60±10``, ``final_tilt<10``, ``torso_height>30cm``,
  ``tracking_error[HeadYaw]<0.2``, ``fall_direction=90±45`` (a direction: ``=`` takes the
  short way round, 180±45 holds for -170). A value without a unit is in the quantity's unit
  (:data:`QUANTITIES`); units: ``m`` ``cm`` ``mm``, ``deg`` ``°`` ``rad``, ``s`` ``ms``.
- an arm's end effector (the report's ``end_effector``): ``ee_error[KEYFRAME]<5mm``,
  ``ee_lag[KEYFRAME]<400ms`` (no keyframe: the worst one), ``ee_deviation<50mm``, and its
  position at a keyframe or a time, a point ``[x, y, z]`` (world frame, m unless a unit
  follows) with a tolerance on the distance: ``ee[place_1]=[0.55,0,0.70]±5mm``,
  ``ee@2.5s=[0.40,0.10,0.30]±0.02``. A keyframe name that several keyframes share (a
  repeated name, ``--loop``) takes the worst of them.
- a flag (:data:`FLAGS`): ``upright``, ``fell``, ``no-fall``, ``no-self-collision``,
  ``feet-planted``. ``upright`` is the play report's fall detector (the root below
  ``fall_height_m`` or tilted past ``fall_tilt_deg``, :class:`motiontool.sim.play.PlayOptions`):
  no fall and up at the end; a stance that leans 11 degrees by design is upright.

An expectation that names the fall (``fell``, ``no-fall``, ``fell_at``, ``fall_direction``)
decides about the fall itself: a robot that falls where ``fell`` is expected is a clean run
(Webots' ``Fall.motion``).

Stdlib only: no simulator is imported here.
"""

from __future__ import annotations

import bisect
import difflib
import math
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.units import MM_PER_M

if TYPE_CHECKING:
    from motiontool.sim.report import PlayReport

__all__ = [
    "FEET_PLANTED_MM",
    "FLAGS",
    "QUANTITIES",
    "Expectation",
    "ExpectationError",
    "ExpectationResult",
    "Quantity",
    "apply_expectations",
    "evaluate",
    "parse_expectation",
    "parse_expectations",
]

FEET_PLANTED_MM = 5.0
"""``feet-planted``: no foot moves further than this (mm, horizontal) from where it started."""


class ExpectationError(MotionToolError):
    """An expectation that cannot be parsed (one line: what was written, what is expected)."""


# A value of the report, in the quantity's unit, and a note ('' or where it was measured:
# 'at pick_1 (2.07 s)'); or None with the reason it was not measured.
Measure = Callable[["PlayReport", "Expectation | None"], tuple["float | None", str]]


@dataclass(frozen=True)
class Quantity:
    """A measurable of a run.

    Attributes:
        name: as written in an expectation.
        unit: its unit (``m``, ``deg``, ``s``, ``mm``, ``rad``; ``""`` for a count).
        help: what it is, one line.
        measure: report, expectation -> (value in ``unit`` and a note, or None and why not
            measured).
        per_joint: whether it takes a joint, ``QUANTITY[JOINT]`` (default: the worst joint).
        decides_fall: an expectation on it replaces the "fell" verdict of the run.
        per_keyframe: whether it takes a keyframe, ``QUANTITY[KEYFRAME]`` (an arm's tool).
        point: whether it is a position, compared with ``=[x, y, z]±TOL`` (the distance is
            measured), at a keyframe ``[KEYFRAME]`` or a time ``@T``.
        periodic: whether it is a direction in degrees, (-180, 180]: ``=`` compares the
            wrapped difference (``fall_direction=180±45`` holds for -170).
    """

    name: str
    unit: str
    help: str
    measure: Measure
    per_joint: bool = False
    decides_fall: bool = False
    per_keyframe: bool = False
    point: bool = False
    periodic: bool = False


_UNITS: dict[str, tuple[str, float]] = {  # unit -> (kind, value in SI)
    "m": ("length", 1.0),
    "cm": ("length", 0.01),
    "mm": ("length", 0.001),
    "deg": ("angle", math.pi / 180.0),
    "°": ("angle", math.pi / 180.0),
    "rad": ("angle", 1.0),
    "s": ("time", 1.0),
    "ms": ("time", 0.001),
}
_DIGITS = {"m": 3, "mm": 1, "deg": 1, "rad": 3, "s": 2, "ms": 0, "": 0}


def _fmt(value: float, unit: str) -> str:
    text = f"{value:.{_DIGITS.get(unit, 3)}f}"
    return f"{text} {unit}" if unit else text


def _g(value: float, unit: str) -> str:
    return f"{value:g} {unit}" if unit else f"{value:g}"


# ------------------------------------------------------------------------------- measures


def _base_value(key: str) -> Measure:
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


def _fall_direction(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
    measured, why = _base_value("fall_direction_deg")(report, e)
    if measured is None and report.base is not None and report.base.fell:
        return None, "the report does not say which way (made before fall_direction existed)"
    return measured, why


def _heading(axis: int) -> Measure:
    def measure(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
        if report.base is None:
            return None, f"{report.robot} has a fixed base: no base motion"
        yaw = math.radians(float(report.options.get("start_yaw_deg") or 0.0))
        dx, dy = report.base.dx_m, report.base.dy_m
        along = dx * math.cos(yaw) + dy * math.sin(yaw)
        left = -dx * math.sin(yaw) + dy * math.cos(yaw)
        return (along if axis == 0 else left), ""

    return measure


def _feet(key: str) -> Measure:
    def measure(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
        if not report.feet:
            return None, f"{report.robot} has no feet"
        return max(float(getattr(f, key)) for f in report.feet) * MM_PER_M, ""

    return measure


def _joint_value(key: str) -> Measure:
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


def _count(key: str) -> Measure:
    def measure(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
        return float(len(getattr(report, key))), ""

    return measure


def _no_tool(report: PlayReport) -> str:
    if report.base is not None:
        return f"{report.robot} has a free-flying base: no end effector is measured"
    return f"{report.robot}: no end effector was measured"


def _keyframes(report: PlayReport, e: Expectation | None) -> tuple[list[Any], str]:
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


def _where(k: Any) -> str:
    return f"at {k.name} ({k.time_s:.2f} s)"


def _ee_error(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
    found, why = _keyframes(report, e)
    if not found:
        return None, why
    worst = max(found, key=lambda k: k.position_error_mm)
    return float(worst.position_error_mm), _where(worst)


def _ee_lag(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
    found, why = _keyframes(report, e)
    if not found:
        return None, why
    assert report.end_effector is not None
    never = [k for k in found if k.lag_ms is None]
    if never:
        k = never[0]
        tol = report.end_effector.reach_tolerance_mm
        return None, (
            f"the tool never came within {tol:g} mm of {k.name} ({k.time_s:.2f} s) before the "
            f"motion moved on (closest at the keyframe time: {k.position_error_mm:.1f} mm)"
        )
    worst = max(found, key=lambda k: float(k.lag_ms))
    return float(worst.lag_ms), _where(worst)


def _ee_deviation(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
    ee = report.end_effector
    if ee is None:
        return None, _no_tool(report)
    return float(ee.max_deviation_mm), f"at {ee.max_deviation_at_s:.2f} s"


def _ee_position(report: PlayReport, e: Expectation | None) -> tuple[float | None, str]:
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
        points += [(k.measured_position_m, _where(k)) for k in found]
    distances = [(math.dist(p, e.point), p, where) for p, where in points]
    distance, p, where = max(distances)
    shown = ", ".join(f"{v:.4f}" for v in p)
    return distance, f"[{shown}] m {where}, {distance * MM_PER_M:.1f} mm away"


QUANTITIES: dict[str, Quantity] = {
    q.name: q
    for q in [
        Quantity("dx", "m", "root displacement along world x, start to end", _base_value("dx_m")),
        Quantity("dy", "m", "root displacement along world y (left)", _base_value("dy_m")),
        Quantity("dz", "m", "root height change, start to end", _base_value("dz_m")),
        Quantity("dx_heading", "m", "displacement along the start heading", _heading(0)),
        Quantity("dy_heading", "m", "displacement to the left of the start heading", _heading(1)),
        Quantity(
            "yaw", "deg", "heading change while upright (+ = left)", _base_value("yaw_change_deg")
        ),
        Quantity(
            "max_tilt", "deg", "largest tilt of the root from vertical", _base_value("max_tilt_deg")
        ),
        Quantity("final_tilt", "deg", "tilt of the root at the end", _base_value("final_tilt_deg")),
        Quantity(
            "torso_height",
            "m",
            "root height above the floor at the end",
            _base_value("final_height_m"),
        ),
        Quantity("min_height", "m", "lowest root height over the run", _base_value("min_height_m")),
        Quantity(
            "fell_at", "s", "when the robot fell", _base_value("fell_at_s"), decides_fall=True
        ),
        Quantity(
            "fall_direction",
            "deg",
            "which way it fell, from its heading before the fall (0 forward, 90 left, "
            "-90 right, 180 back)",
            _fall_direction,
            decides_fall=True,
            periodic=True,
        ),
        Quantity(
            "feet_slip",
            "mm",
            "largest horizontal slip of a foot while on the floor",
            _feet("slip_m"),
        ),
        Quantity(
            "feet_moved",
            "mm",
            "furthest a foot got from where it started",
            _feet("max_displacement_m"),
        ),
        Quantity(
            "tracking_error",
            "rad",
            "largest |target - position| (m for a linear joint)",
            _joint_value("max_error"),
            per_joint=True,
        ),
        Quantity(
            "tracking_rms",
            "rad",
            "RMS of target - position (m for a linear joint)",
            _joint_value("rms_error"),
            per_joint=True,
        ),
        Quantity(
            "velocity_cap",
            "s",
            "time a motor's command sat at maxVelocity",
            _joint_value("velocity_cap_s"),
            per_joint=True,
        ),
        Quantity(
            "torque_cap",
            "s",
            "time a motor's torque sat at maxTorque",
            _joint_value("torque_cap_s"),
            per_joint=True,
        ),
        Quantity(
            "self_collisions", "", "pairs of robot bodies that collided", _count("self_collisions")
        ),
        Quantity(
            "ee_error",
            "mm",
            "an arm's tool: distance from the keyframe's forward kinematics at its time",
            _ee_error,
            per_keyframe=True,
        ),
        Quantity(
            "ee_lag",
            "ms",
            "an arm's tool: time after the keyframe until within the reach tolerance",
            _ee_lag,
            per_keyframe=True,
        ),
        Quantity(
            "ee_deviation",
            "mm",
            "an arm's tool: largest distance from the forward kinematics of the commands",
            _ee_deviation,
        ),
        Quantity(
            "ee",
            "m",
            "an arm's tool position at [KEYFRAME] or @TIME: distance from a point [x,y,z]",
            _ee_position,
            per_keyframe=True,
            point=True,
        ),
        Quantity(
            "scene_contacts",
            "",
            "pairs robot / scene (not the floor) that touched",
            _count("scene_contacts"),
        ),
    ]
}
"""Every quantity an expectation can name: name -> :class:`Quantity` (units in ``unit``; the
per-joint ones take the worst commanded joint unless a joint is named in brackets)."""

FLAGS: dict[str, str] = {
    "upright": "no fall and up at the end (the fall detector: root height and tilt)",
    "fell": "the robot falls (the fall is then expected: not a failure)",
    "no-fall": "the robot does not fall",
    "no-self-collision": "no two robot bodies collide",
    "feet-planted": f"no foot moves more than {FEET_PLANTED_MM:g} mm from where it started",
}
"""Bare-word expectations and what they require."""

_FLAG_DECIDES_FALL = {"fell", "no-fall"}


# ------------------------------------------------------------------------------- parsing


@dataclass(frozen=True)
class Expectation:
    """One expectation.

    Attributes:
        text: as written.
        quantity: a :data:`QUANTITIES` name, or a :data:`FLAGS` name (then ``op`` is None).
        op: ``<``, ``<=``, ``>``, ``>=``, ``=``, or None for a flag.
        value: the bound, in the quantity's unit.
        tolerance: for ``=``, the allowed deviation, in the quantity's unit (>= 0).
        joint: the joint of a per-joint quantity, or None for the worst one.
        keyframe: the keyframe (pose name) of an end-effector quantity, or None.
        at_s: the time of an ``ee@T`` position, s, or None.
        point: the point of an ``ee`` position, world frame, m, or None.
    """

    text: str
    quantity: str
    op: str | None = None
    value: float = 0.0
    tolerance: float = 0.0
    joint: str | None = None
    keyframe: str | None = None
    at_s: float | None = None
    point: tuple[float, float, float] | None = None

    @property
    def unit(self) -> str:
        q = QUANTITIES.get(self.quantity)
        return q.unit if q is not None else ""

    @property
    def decides_fall(self) -> bool:
        if self.op is None:
            return self.quantity in _FLAG_DECIDES_FALL
        return QUANTITIES[self.quantity].decides_fall

    def describe(self) -> str:
        """``dx >= 0.3 m``, ``yaw = 60 ± 10 deg``, ``upright (no fall, ...)``."""
        if self.op is None:
            return f"{self.quantity} ({FLAGS[self.quantity]})"
        name = self.quantity + (f"[{self.joint}]" if self.joint else "")
        if self.keyframe is not None:
            name += f"[{self.keyframe}]"
        if self.at_s is not None:
            name += f"@{self.at_s:g}s"
        if self.point is not None:
            point = "[" + ", ".join(f"{v:g}" for v in self.point) + "]"
            return f"{name} {self.op} {point} ± {_g(self.tolerance, self.unit)}"
        if self.op == "=":
            value = f"{self.value:g} ± {_g(self.tolerance, self.unit)}"
        else:
            value = _g(self.value, self.unit)
        return f"{name} {self.op} {value}"


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_PATTERN = re.compile(
    rf"""^\s*(?P<name>[A-Za-z][\w-]*)\s*(?:\[\s*(?P<joint>[^\]]*?)\s*\])?\s*
    (?:@\s*(?P<at>{_NUMBER})\s*(?P<at_unit>[A-Za-z]*)\s*)?
    (?P<op><=|>=|==|=|<|>|≤|≥)\s*
    (?:(?P<value>{_NUMBER})|\[(?P<point>[^\]]*)\])\s*(?P<unit>[A-Za-z°%]*)\s*
    (?:(?:±|\+/-|\+-)\s*(?P<tol>{_NUMBER})\s*(?P<tol_unit>[A-Za-z°%]*))?\s*$""",
    re.VERBOSE,
)
_OPS = {"==": "=", "≤": "<=", "≥": ">="}


def _valid_names() -> str:
    return ", ".join([*QUANTITIES, *FLAGS])


def _unknown(name: str, text: str) -> ExpectationError:
    choices = [*QUANTITIES, *FLAGS]
    close = difflib.get_close_matches(name, choices, n=1, cutoff=0.6)
    hint = f"; did you mean '{close[0]}'?" if close else ""
    return ExpectationError(
        f"expectation {text!r}: unknown quantity '{name}'{hint} (valid: {_valid_names()})"
    )


def _convert(number: float, unit: str, quantity: Quantity, text: str) -> float:
    """``number`` written in ``unit`` (``""``: the quantity's own) in the quantity's unit."""
    if not unit or unit == quantity.unit:
        return number
    kind = _UNITS[quantity.unit][0] if quantity.unit else "count"
    if unit not in _UNITS or _UNITS[unit][0] != kind:
        own = quantity.unit or "a plain count"
        valid = [u for u, (k, _f) in _UNITS.items() if k == kind]
        choices = f" ({', '.join(valid)})" if valid else ""
        raise ExpectationError(
            f"expectation {text!r}: unit '{unit}' does not fit {quantity.name}, "
            f"which is in {own}{choices}"
        )
    return number * _UNITS[unit][1] / _UNITS[quantity.unit][1]


def parse_expectation(text: str) -> Expectation:
    """Parse one expectation (see the module docstring).

    Raises:
        ExpectationError: one line naming what was written and what is expected, with the
            valid quantities and a did-you-mean for an unknown one.
    """
    flag = text.strip().lower().replace("_", "-")
    if flag in FLAGS:
        return Expectation(text, flag)
    m = _PATTERN.match(text)
    if m is None:
        word = re.match(r"\s*([A-Za-z][\w-]*)", text)
        if word and word.group(1) not in QUANTITIES and word.group(1).lower() not in FLAGS:
            raise _unknown(word.group(1), text)
        raise ExpectationError(
            f"expectation {text!r}: expected QUANTITY OP VALUE[UNIT] (OP: < <= > >= =, "
            f"'=' with ±TOL), e.g. 'dx>=0.3' or 'yaw=60±10', or a flag ({', '.join(FLAGS)})"
        )
    name = m.group("name")
    quantity = QUANTITIES.get(name)
    if quantity is None:
        raise _unknown(name, text)
    joint = m.group("joint")
    keyframe: str | None = None
    if joint is not None and quantity.per_keyframe:
        keyframe, joint = joint, None
        if keyframe == "":
            raise ExpectationError(f"expectation {text!r}: empty keyframe name in []")
    elif joint is not None and not quantity.per_joint:
        per_joint = ", ".join(q.name for q in QUANTITIES.values() if q.per_joint)
        per_keyframe = ", ".join(q.name for q in QUANTITIES.values() if q.per_keyframe)
        raise ExpectationError(
            f"expectation {text!r}: {name} takes no joint (only {per_joint} do) and no keyframe"
            f" (only {per_keyframe} do)"
        )
    if joint == "":
        raise ExpectationError(f"expectation {text!r}: empty joint name in []")
    op = _OPS.get(m.group("op"), m.group("op"))
    if m.group("unit") == "%":
        raise ExpectationError(f"expectation {text!r}: '%' is for a tolerance (yaw=60±15%)")
    unit = m.group("unit")
    if not unit and m.group("tol_unit") not in (None, "", "%"):
        unit = m.group("tol_unit")  # 'yaw=60±10deg': the unit is the value's too
    at_s, point = _where_and_point(m, quantity, keyframe, op, text)
    if point is not None:  # in m, or in the unit right after it: '±5mm' is the tolerance's
        unit = m.group("unit")
        point = (
            _convert(point[0], unit, quantity, text),
            _convert(point[1], unit, quantity, text),
            _convert(point[2], unit, quantity, text),
        )
    value = 0.0 if point is not None else _convert(float(m.group("value")), unit, quantity, text)
    tolerance = 0.0
    if m.group("tol") is not None:
        if op != "=":
            raise ExpectationError(f"expectation {text!r}: ±TOL goes with '=' only")
        tol = float(m.group("tol"))
        if m.group("tol_unit") == "%" and point is not None:
            raise ExpectationError(f"expectation {text!r}: a point's tolerance is a distance")
        if m.group("tol_unit") == "%":
            tolerance = abs(value) * tol / 100.0
        else:
            tolerance = _convert(tol, m.group("tol_unit"), quantity, text)
        if not (math.isfinite(tolerance) and tolerance >= 0):
            raise ExpectationError(f"expectation {text!r}: the tolerance must be >= 0")
    elif op == "=" and quantity.unit:
        example = m.group("value") or f"[{m.group('point')}]"
        raise ExpectationError(
            f"expectation {text!r}: '=' needs a tolerance, e.g. '{name}={example}±1'"
        )
    if not math.isfinite(value) or (point is not None and not all(map(math.isfinite, point))):
        raise ExpectationError(f"expectation {text!r}: the value must be a finite number")
    if point is not None:
        value = tolerance  # the distance from the point must be at most the tolerance
    return Expectation(text, name, op, value, tolerance, joint, keyframe, at_s, point)


def _where_and_point(
    m: re.Match[str], quantity: Quantity, keyframe: str | None, op: str, text: str
) -> tuple[float | None, tuple[float, float, float] | None]:
    """The ``@T`` time (s) and the ``[x, y, z]`` point of an expectation, checked."""
    name = quantity.name
    at_s: float | None = None
    if m.group("at") is not None:
        if not quantity.point:
            raise ExpectationError(
                f"expectation {text!r}: {name} takes no time (only ee@T=[x,y,z]±TOL does)"
            )
        at_unit = m.group("at_unit") or "s"
        if at_unit not in ("s", "ms"):
            raise ExpectationError(f"expectation {text!r}: the time after '@' is in s or ms")
        at_s = float(m.group("at")) * _UNITS[at_unit][1]
        if not (math.isfinite(at_s) and at_s >= 0):
            raise ExpectationError(f"expectation {text!r}: the time after '@' must be >= 0")
    raw = m.group("point")
    if not quantity.point:
        if raw is not None:
            raise ExpectationError(f"expectation {text!r}: {name} takes a number, not [x, y, z]")
        return at_s, None
    example = "'ee[place_1]=[0.55,0,0.70]±5mm' or 'ee@2.5s=[0.4,0.1,0.3]±0.02'"
    if raw is None or op != "=":
        raise ExpectationError(
            f"expectation {text!r}: {name} is a position: write {name}[KEYFRAME] or {name}@T,"
            f" '=', a point [x, y, z] and ±TOL, e.g. {example}"
        )
    if (keyframe is None) == (at_s is None):
        raise ExpectationError(
            f"expectation {text!r}: {name} needs one keyframe [KEYFRAME] or one time @T,"
            f" e.g. {example}"
        )
    parts = [v.strip() for v in raw.split(",")]
    if len(parts) != 3 or not all(re.fullmatch(_NUMBER, v) for v in parts):
        raise ExpectationError(
            f"expectation {text!r}: expected a point of 3 numbers [x, y, z], found [{raw}]"
        )
    return at_s, (float(parts[0]), float(parts[1]), float(parts[2]))


def parse_expectations(texts: Iterable[str]) -> list[Expectation]:
    """Parse every text (the first bad one raises :class:`ExpectationError`)."""
    return [parse_expectation(t) for t in texts]


# ------------------------------------------------------------------------------- judging


@dataclass(frozen=True)
class ExpectationResult:
    """An expectation judged on a run.

    Attributes:
        expectation: what was expected.
        passed: whether the run meets it.
        measured: the value measured, in ``unit`` (None: not measured; the reason says why).
        unit: the unit of ``measured``.
        reason: one line, ``expected dx >= 0.3 m, measured 0.120 m``; empty when passed.
    """

    expectation: Expectation
    passed: bool
    measured: float | None
    unit: str
    reason: str = ""

    def to_json(self) -> dict[str, Any]:
        """``{"text", "quantity", "joint", "expected", "passed", "measured": {"value",
        "unit"}, "reason"}`` (a value that is not finite, or not measured, is null)."""
        value = self.measured
        doc: dict[str, Any] = {
            "text": self.expectation.text,
            "quantity": self.expectation.quantity,
            "joint": self.expectation.joint,
            "expected": self.expectation.describe(),
            "passed": self.passed,
            "measured": {
                "value": value if value is not None and math.isfinite(value) else None,
                "unit": self.unit,
            },
            "reason": self.reason,
        }
        e = self.expectation
        if e.keyframe is not None:
            doc["keyframe"] = e.keyframe
        if e.at_s is not None:
            doc["at_s"] = e.at_s
        if e.point is not None:
            doc["point_m"] = list(e.point)
        return doc

    def summary(self) -> str:
        """One line for people: ``ok   dx >= 0.3 m: 0.470 m`` or ``FAIL <reason>``."""
        if not self.passed:
            return f"FAIL {self.reason}"
        shown = "" if self.measured is None else f": {_fmt(self.measured, self.unit)}"
        if self.expectation.point is not None and self.measured is not None:
            shown = f": {self.measured * MM_PER_M:.1f} mm away"
        return f"ok   {self.expectation.describe()}{shown}"


def _flag(e: Expectation, report: PlayReport) -> ExpectationResult:
    name = e.quantity
    if name == "no-self-collision":
        pairs = report.self_collisions
        first = (
            f" ({pairs[0].body_a}/{pairs[0].body_b} at {pairs[0].first_s:.2f} s)" if pairs else ""
        )
        return ExpectationResult(
            e,
            not pairs,
            float(len(pairs)),
            "",
            "" if not pairs else f"expected no self-collision, measured {len(pairs)}{first}",
        )
    if name == "feet-planted":
        moved, why = _feet("max_displacement_m")(report, None)
        if moved is None:
            return ExpectationResult(e, False, None, "mm", f"expected feet planted, {why}")
        ok = moved < FEET_PLANTED_MM
        bound = f"< {FEET_PLANTED_MM:g} mm"
        reason = "" if ok else f"expected feet planted ({bound}), a foot moved {_fmt(moved, 'mm')}"
        return ExpectationResult(e, ok, moved, "mm", reason)
    base = report.base
    if base is None:
        why = f"{report.robot} has a fixed base: it cannot fall"
        return ExpectationResult(e, False, None, "", f"expected {name}, not measured: {why}")
    fell_at = f"fell at {base.fell_at_s:.2f} s" if base.fell_at_s is not None else "fell"
    if name == "fell":
        reason = "" if base.fell else "expected a fall, the robot did not fall"
        return ExpectationResult(e, base.fell, base.fell_at_s, "s", reason)
    if name == "no-fall":
        reason = f"expected no fall, {fell_at}" if base.fell else ""
        return ExpectationResult(e, not base.fell, base.fell_at_s, "s", reason)
    # upright: the fall detector's verdict (final tilt measured, for the reader)
    tilt = base.final_tilt_deg
    if base.fell:
        problem = fell_at
    elif not base.upright_at_end:
        problem = "down at the end" + (" (started down)" if base.started_down else "")
    else:
        return ExpectationResult(e, True, tilt, "deg")
    reason = f"expected upright (no fall, up at the end), {problem}"
    return ExpectationResult(e, False, tilt, "deg", reason)


def _compare(
    op: str, measured: float, value: float, tolerance: float, periodic: bool = False
) -> bool:
    if op == "=" and periodic:  # directions, degrees: the short way round
        return abs((measured - value + 180.0) % 360.0 - 180.0) <= tolerance
    if op == "<":
        return measured < value
    if op == "<=":
        return measured <= value
    if op == ">":
        return measured > value
    if op == ">=":
        return measured >= value
    return abs(measured - value) <= tolerance


def evaluate(
    expectations: Sequence[Expectation | str], report: PlayReport
) -> list[ExpectationResult]:
    """Judge every expectation on ``report`` (texts are parsed first)."""
    out = []
    for item in expectations:
        e = parse_expectation(item) if isinstance(item, str) else item
        if e.op is None:
            out.append(_flag(e, report))
            continue
        quantity = QUANTITIES[e.quantity]
        measured, note = quantity.measure(report, e)
        if measured is None:
            reason = f"expected {e.describe()}, not measured: {note}"
            out.append(ExpectationResult(e, False, None, quantity.unit, reason))
            continue
        if e.point is not None:  # a position: the distance from the point, within the tolerance
            ok = math.isfinite(measured) and measured <= e.tolerance
            reason = "" if ok else f"expected {e.describe()}, measured {note}"
        else:
            ok = math.isfinite(measured) and _compare(
                e.op, measured, e.value, e.tolerance, quantity.periodic
            )
            shown = _fmt(measured, quantity.unit) + (f" ({note})" if note else "")
            reason = "" if ok else f"expected {e.describe()}, measured {shown}"
        out.append(ExpectationResult(e, ok, measured, quantity.unit, reason))
    return out


def apply_expectations(doc: dict[str, Any], expectations: Sequence[str]) -> dict[str, Any]:
    """A copy of the play report ``doc`` (JSON, ``motiontool.play``) with ``expectations``
    judged: ``expectations``, ``clean``, ``exit_code`` and ``reason`` updated, every other key
    kept (a batch caches the raw report and judges it after the cache)."""
    from motiontool.sim.report import PlayReport

    report = PlayReport.from_json(doc)
    report.expectations = evaluate(expectations, report)
    out = dict(doc)
    out.update(report.to_json())
    return out
