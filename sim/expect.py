"""Behaviour expectations of a run: ``dx>=0.3``, ``yaw=60±10``, ``upright``, judged on a report.

A run is *clean* when the robot does not fall, nothing collides and the simulator raises no
warning; an expectation says what the motion must also *do*. Two forms:

- ``QUANTITY OP VALUE[UNIT]`` with OP one of ``<`` ``<=`` ``>`` ``>=`` ``=`` (``=`` needs a
  tolerance: ``±TOL[UNIT]``, also written ``+-TOL``, or ``±P%`` of the value; a unit after
  the tolerance alone applies to the value too: ``torso_height=33±1cm``), e.g.
  ``dx>=0.3``, ``yaw=60±10``, ``final_tilt<10``, ``torso_height>30cm``,
  ``tracking_error[HeadYaw]<0.2``. A value without a unit is in the quantity's unit
  (:data:`QUANTITIES`); units: ``m`` ``cm`` ``mm``, ``deg`` ``°`` ``rad``, ``s`` ``ms``.
- a flag (:data:`FLAGS`): ``upright``, ``fell``, ``no-fall``, ``no-self-collision``,
  ``feet-planted``.

An expectation that names the fall (``fell``, ``no-fall``, ``fell_at``) decides about the fall
itself: a robot that falls where ``fell`` is expected is a clean run (Webots' ``Fall.motion``).

Stdlib only: no simulator is imported here.
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.errors import MotionToolError

if TYPE_CHECKING:
    from motiontool.sim.report import PlayReport

__all__ = [
    "FEET_PLANTED_MM",
    "FLAGS",
    "QUANTITIES",
    "UPRIGHT_TILT_DEG",
    "Expectation",
    "ExpectationError",
    "ExpectationResult",
    "Quantity",
    "apply_expectations",
    "evaluate",
    "parse_expectation",
    "parse_expectations",
]

UPRIGHT_TILT_DEG = 10.0
"""``upright``: no fall, up at the end, and the final tilt (degrees) below this."""

FEET_PLANTED_MM = 5.0
"""``feet-planted``: no foot moves further than this (mm, horizontal) from where it started."""


class ExpectationError(MotionToolError):
    """An expectation that cannot be parsed (one line: what was written, what is expected)."""


# A value of the report, in the quantity's unit, or None with the reason it was not measured.
Measure = Callable[["PlayReport", "str | None"], tuple["float | None", str]]


@dataclass(frozen=True)
class Quantity:
    """A measurable of a run.

    Attributes:
        name: as written in an expectation.
        unit: its unit (``m``, ``deg``, ``s``, ``mm``, ``rad``; ``""`` for a count).
        help: what it is, one line.
        measure: report, joint -> (value in ``unit``, or None and why not measured).
        per_joint: whether it takes a joint, ``QUANTITY[JOINT]`` (default: the worst joint).
        decides_fall: an expectation on it replaces the "fell" verdict of the run.
    """

    name: str
    unit: str
    help: str
    measure: Measure
    per_joint: bool = False
    decides_fall: bool = False


_KIND = {"m": "length", "deg": "angle", "rad": "angle", "s": "time", "mm": "length", "": "count"}
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
_DIGITS = {"m": 3, "mm": 1, "deg": 1, "rad": 3, "s": 2, "": 0}


def _fmt(value: float, unit: str) -> str:
    text = f"{value:.{_DIGITS.get(unit, 3)}f}"
    return f"{text} {unit}" if unit else text


def _g(value: float, unit: str) -> str:
    return f"{value:g} {unit}" if unit else f"{value:g}"


# ------------------------------------------------------------------------------- measures


def _base_value(key: str) -> Measure:
    def measure(report: PlayReport, joint: str | None) -> tuple[float | None, str]:
        if report.base is None:
            return None, f"{report.robot} has a fixed base: no base motion"
        value = getattr(report.base, key)
        if value is None:
            why = {
                "yaw_change_deg": "the robot was never upright",
                "fell_at_s": "it did not fall",
            }.get(key, "no value")
            return None, why
        return float(value), ""

    return measure


def _heading(axis: int) -> Measure:
    def measure(report: PlayReport, joint: str | None) -> tuple[float | None, str]:
        if report.base is None:
            return None, f"{report.robot} has a fixed base: no base motion"
        yaw = math.radians(float(report.options.get("start_yaw_deg") or 0.0))
        dx, dy = report.base.dx_m, report.base.dy_m
        along = dx * math.cos(yaw) + dy * math.sin(yaw)
        left = -dx * math.sin(yaw) + dy * math.cos(yaw)
        return (along if axis == 0 else left), ""

    return measure


def _feet(key: str) -> Measure:
    def measure(report: PlayReport, joint: str | None) -> tuple[float | None, str]:
        if not report.feet:
            return None, f"{report.robot} has no feet"
        return max(float(getattr(f, key)) for f in report.feet) * 1000.0, ""

    return measure


def _joint_value(key: str) -> Measure:
    def measure(report: PlayReport, joint: str | None) -> tuple[float | None, str]:
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
    def measure(report: PlayReport, joint: str | None) -> tuple[float | None, str]:
        return float(len(getattr(report, key))), ""

    return measure


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
    "upright": f"no fall, up at the end and final tilt < {UPRIGHT_TILT_DEG:g} deg",
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
    """

    text: str
    quantity: str
    op: str | None = None
    value: float = 0.0
    tolerance: float = 0.0
    joint: str | None = None

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
        if self.op == "=":
            value = f"{self.value:g} ± {_g(self.tolerance, self.unit)}"
        else:
            value = _g(self.value, self.unit)
        return f"{name} {self.op} {value}"


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_PATTERN = re.compile(
    rf"""^\s*(?P<name>[A-Za-z][\w-]*)\s*(?:\[\s*(?P<joint>[^\]]*?)\s*\])?\s*
    (?P<op><=|>=|==|=|<|>|≤|≥)\s*
    (?P<value>{_NUMBER})\s*(?P<unit>[A-Za-z°%]*)\s*
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
    kind = _KIND[quantity.unit]
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
    if joint is not None and not quantity.per_joint:
        per_joint = ", ".join(q.name for q in QUANTITIES.values() if q.per_joint)
        raise ExpectationError(f"expectation {text!r}: {name} takes no joint (only {per_joint} do)")
    if joint == "":
        raise ExpectationError(f"expectation {text!r}: empty joint name in []")
    op = _OPS.get(m.group("op"), m.group("op"))
    if m.group("unit") == "%":
        raise ExpectationError(f"expectation {text!r}: '%' is for a tolerance (yaw=60±15%)")
    unit = m.group("unit")
    if not unit and m.group("tol_unit") not in (None, "", "%"):
        unit = m.group("tol_unit")  # 'yaw=60±10deg': the unit is the value's too
    value = _convert(float(m.group("value")), unit, quantity, text)
    tolerance = 0.0
    if m.group("tol") is not None:
        if op != "=":
            raise ExpectationError(f"expectation {text!r}: ±TOL goes with '=' only")
        tol = float(m.group("tol"))
        if m.group("tol_unit") == "%":
            tolerance = abs(value) * tol / 100.0
        else:
            tolerance = _convert(tol, m.group("tol_unit"), quantity, text)
        if not (math.isfinite(tolerance) and tolerance >= 0):
            raise ExpectationError(f"expectation {text!r}: the tolerance must be >= 0")
    elif op == "=" and quantity.unit:
        raise ExpectationError(
            f"expectation {text!r}: '=' needs a tolerance, e.g. '{name}={m.group('value')}±1'"
        )
    if not math.isfinite(value):
        raise ExpectationError(f"expectation {text!r}: the value must be a finite number")
    return Expectation(text, name, op, value, tolerance, joint)


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
        return {
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

    def summary(self) -> str:
        """One line for people: ``ok   dx >= 0.3 m: 0.470 m`` or ``FAIL <reason>``."""
        if not self.passed:
            return f"FAIL {self.reason}"
        shown = "" if self.measured is None else f": {_fmt(self.measured, self.unit)}"
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
    # upright
    tilt = base.final_tilt_deg
    if base.fell:
        problem = fell_at
    elif not base.upright_at_end:
        problem = "down at the end" + (" (started down)" if base.started_down else "")
    elif not tilt < UPRIGHT_TILT_DEG:
        problem = f"final tilt {_fmt(tilt, 'deg')}"
    else:
        return ExpectationResult(e, True, tilt, "deg")
    reason = f"expected upright (no fall, final tilt < {UPRIGHT_TILT_DEG:g} deg), {problem}"
    return ExpectationResult(e, False, tilt, "deg", reason)


def _compare(op: str, measured: float, value: float, tolerance: float) -> bool:
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
        measured, why = quantity.measure(report, e.joint)
        if measured is None:
            reason = f"expected {e.describe()}, not measured: {why}"
            out.append(ExpectationResult(e, False, None, quantity.unit, reason))
            continue
        ok = math.isfinite(measured) and _compare(e.op, measured, e.value, e.tolerance)
        reason = "" if ok else f"expected {e.describe()}, measured {_fmt(measured, quantity.unit)}"
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
