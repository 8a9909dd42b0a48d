"""The grammar of an expectation: ``dx>=0.3``, ``yaw=60±10``, ``upright``, parsed into an
:class:`Expectation` (judged by :func:`motiontool.sim.expect.evaluate`). The forms:

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
  ``fall_height_m`` or tilted past ``fall_tilt_deg``, :class:`motiontool.sim.play.PlayOptions`,
  up again a margin past both): no fall and up at the end; a stance that leans 11 degrees by
  design is upright.

Stdlib only: no simulator is imported here.
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Iterable
from dataclasses import dataclass

from motiontool.errors import MotionToolError
from motiontool.sim.quantities import (
    FLAGS,
    FLAGS_DECIDING_FALL,
    QUANTITIES,
    UNITS,
    Quantity,
    format_number,
)

__all__ = ["Expectation", "ExpectationError", "parse_expectation", "parse_expectations"]


class ExpectationError(MotionToolError):
    """An expectation that cannot be parsed (one line: what was written, what is expected)."""


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
            return self.quantity in FLAGS_DECIDING_FALL
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
            return f"{name} {self.op} {point} ± {format_number(self.tolerance, self.unit)}"
        if self.op == "=":
            value = f"{self.value:g} ± {format_number(self.tolerance, self.unit)}"
        else:
            value = format_number(self.value, self.unit)
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
    kind = UNITS[quantity.unit][0] if quantity.unit else "count"
    if unit not in UNITS or UNITS[unit][0] != kind:
        own = quantity.unit or "a plain count"
        valid = [u for u, (k, _f) in UNITS.items() if k == kind]
        choices = f" ({', '.join(valid)})" if valid else ""
        raise ExpectationError(
            f"expectation {text!r}: unit '{unit}' does not fit {quantity.name}, "
            f"which is in {own}{choices}"
        )
    return number * UNITS[unit][1] / UNITS[quantity.unit][1]


def parse_expectation(text: str) -> Expectation:
    """Parse one expectation (see the module docstring).

    Raises:
        ExpectationError: one line naming what was written and what is expected, with the
            valid quantities and a did-you-mean for an unknown one.
    """
    flag = text.strip().lower().replace("_", "-")
    if flag in FLAGS:
        return Expectation(text, flag)
    m = _match(text)
    name = m.group("name")
    quantity = QUANTITIES.get(name)
    if quantity is None:
        raise _unknown(name, text)
    joint, keyframe = _subject(m, quantity, text)
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
    tolerance = _tolerance(m, quantity, op, value, point is not None, text)
    if not math.isfinite(value) or (point is not None and not all(map(math.isfinite, point))):
        raise ExpectationError(f"expectation {text!r}: the value must be a finite number")
    if point is not None:
        value = tolerance  # the distance from the point must be at most the tolerance
    return Expectation(text, name, op, value, tolerance, joint, keyframe, at_s, point)


def _match(text: str) -> re.Match[str]:
    """``text`` matched by the grammar; an unknown quantity or a malformed expectation raise."""
    m = _PATTERN.match(text)
    if m is not None:
        return m
    word = re.match(r"\s*([A-Za-z][\w-]*)", text)
    if word and word.group(1) not in QUANTITIES and word.group(1).lower() not in FLAGS:
        raise _unknown(word.group(1), text)
    raise ExpectationError(
        f"expectation {text!r}: expected QUANTITY OP VALUE[UNIT] (OP: < <= > >= =, "
        f"'=' with ±TOL), e.g. 'dx>=0.3' or 'yaw=60±10', or a flag ({', '.join(FLAGS)})"
    )


def _subject(m: re.Match[str], quantity: Quantity, text: str) -> tuple[str | None, str | None]:
    """The ``[JOINT]`` or ``[KEYFRAME]`` of an expectation, as (joint, keyframe), checked against
    what ``quantity`` takes."""
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
            f"expectation {text!r}: {quantity.name} takes no joint (only {per_joint} do) and no"
            f" keyframe (only {per_keyframe} do)"
        )
    if joint == "":
        raise ExpectationError(f"expectation {text!r}: empty joint name in []")
    return joint, keyframe


def _tolerance(
    m: re.Match[str], quantity: Quantity, op: str, value: float, is_point: bool, text: str
) -> float:
    """The ``±TOL`` of an expectation in the quantity's unit (``±P%``: of ``value``), >= 0; 0
    without one. ``=`` on a quantity with a unit needs one."""
    if m.group("tol") is None:
        if op == "=" and quantity.unit:
            example = m.group("value") or f"[{m.group('point')}]"
            raise ExpectationError(
                f"expectation {text!r}: '=' needs a tolerance, e.g. '{quantity.name}={example}±1'"
            )
        return 0.0
    if op != "=":
        raise ExpectationError(f"expectation {text!r}: ±TOL goes with '=' only")
    tol = float(m.group("tol"))
    if m.group("tol_unit") == "%" and is_point:
        raise ExpectationError(f"expectation {text!r}: a point's tolerance is a distance")
    if m.group("tol_unit") == "%":
        tolerance = abs(value) * tol / 100.0
    else:
        tolerance = _convert(tol, m.group("tol_unit"), quantity, text)
    if not (math.isfinite(tolerance) and tolerance >= 0):
        raise ExpectationError(f"expectation {text!r}: the tolerance must be >= 0")
    return tolerance


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
        at_s = float(m.group("at")) * UNITS[at_unit][1]
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
