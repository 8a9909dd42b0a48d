"""Behaviour expectations of a run, judged on its report: what ``play``, ``batch`` and a
``motions.toml`` sidecar ask of a motion besides a clean run.

A run is *clean* when the robot does not fall, nothing collides and the simulator raises no
warning; an expectation says what the motion must also *do*. Three modules, one concept each:
the grammar (:mod:`motiontool.sim.expect_syntax`: ``dx>=0.3``, ``yaw=60±10``, ``upright``, ...
parsed into an :class:`Expectation`), the quantities and flags it may name
(:mod:`motiontool.sim.quantities`, each read off the report by
:mod:`motiontool.sim.report_values`), and here the judgement (:func:`evaluate`). This module
is the one to import: it re-exports the parser and the registry.

An expectation that names the fall (``fell``, ``no-fall``, ``fell_at``, ``fall_direction``)
decides about the fall itself: a robot that falls where ``fell`` is expected is a clean run
(Webots' ``Fall.motion``).

Stdlib only: no simulator is imported here.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.units import MM_PER_M
from motiontool.sim.expect_syntax import (
    Expectation,
    ExpectationError,
    parse_expectation,
    parse_expectations,
)
from motiontool.sim.quantities import (
    FEET_PLANTED_MM,
    FLAGS,
    QUANTITIES,
    Quantity,
    format_measured,
)
from motiontool.sim.report_values import feet

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
        shown = "" if self.measured is None else f": {format_measured(self.measured, self.unit)}"
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
        moved, why = feet("max_displacement_m")(report, None)
        if moved is None:
            return ExpectationResult(e, False, None, "mm", f"expected feet planted, {why}")
        ok = moved < FEET_PLANTED_MM
        bound = f"< {FEET_PLANTED_MM:g} mm"
        moved_mm = format_measured(moved, "mm")
        reason = "" if ok else f"expected feet planted ({bound}), a foot moved {moved_mm}"
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
            shown = format_measured(measured, quantity.unit) + (f" ({note})" if note else "")
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
