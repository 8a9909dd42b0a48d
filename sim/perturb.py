"""The perturbations of a batch: ``--perturb NAME=LOW:HIGH``, each NAME's meaning and the
values it takes (:data:`PERTURBATIONS`), parsed and checked before any run
(:func:`parse_perturbation`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from motiontool.errors import MotionToolError

__all__ = ["PERTURBATIONS", "Perturbation", "PerturbationKind", "parse_perturbation"]


@dataclass(frozen=True)
class PerturbationKind:
    """What ``--perturb NAME=LOW:HIGH`` draws for one NAME.

    Attributes:
        meaning: what a value is, with its unit (a factor: 1 = nominal).
        above: the values taken are above this one (-inf: any finite number).
        inclusive: whether ``above`` itself is taken (``>=``; else ``>``).
    """

    meaning: str
    above: float = -math.inf
    inclusive: bool = False

    @property
    def values(self) -> str:
        """The values taken, for people: ``> 0``, ``>= 0`` or ``any finite number``."""
        if self.above == -math.inf:
            return "any finite number"
        return f"{'>=' if self.inclusive else '>'} {self.above:g}"

    def takes(self, value: float) -> bool:
        """Whether ``value`` (finite) is one of the values taken."""
        return value >= self.above if self.inclusive else value > self.above


PERTURBATIONS: dict[str, PerturbationKind] = {
    "friction": PerturbationKind("a factor on the floor friction", 0.0),
    "mass": PerturbationKind("a factor on every body mass", 0.0),
    "motor-strength": PerturbationKind("a factor on every motor's maxTorque", 0.0),
    "start-yaw": PerturbationKind("the start heading, deg"),
    "start-noise": PerturbationKind(
        "the standard deviation of the start joint offsets, rad", 0.0, inclusive=True
    ),
    "speed": PerturbationKind("a factor on the playback speed", 0.0),
}
"""Perturbation names for ``--perturb NAME=LOW:HIGH``, what they draw and the values they take
(a factor of 1: as without the perturbation; ``friction`` scales ``--friction``, else the
profile's). A mass, a torque limit or a speed of 0 or less cannot be played, a standard
deviation below 0 is none: refused where parsed, before any run."""


@dataclass(frozen=True)
class Perturbation:
    """A uniform range ``[low, high]`` for one perturbation parameter."""

    name: str
    low: float
    high: float


def parse_perturbation(text: str) -> Perturbation:
    """``friction=0.7:1.3`` -> Perturbation; a one-line error naming the valid names, or the
    values the name takes (:data:`PERTURBATIONS`), otherwise."""
    name, sep, bounds = text.partition("=")
    name = name.strip()
    if not sep or name not in PERTURBATIONS:
        raise MotionToolError(
            f"perturbation {text!r}: expected NAME=LOW:HIGH, NAME one of "
            + ", ".join(PERTURBATIONS)
        )
    low_s, colon, high_s = bounds.partition(":")
    try:
        low = float(low_s)
        high = float(high_s) if colon else low
    except ValueError:
        raise MotionToolError(f"perturbation {text!r}: LOW and HIGH must be numbers") from None
    if not (math.isfinite(low) and math.isfinite(high)) or high < low:
        raise MotionToolError(f"perturbation {text!r}: need finite LOW <= HIGH")
    kind = PERTURBATIONS[name]
    if not kind.takes(low):  # HIGH >= LOW: in range too
        raise MotionToolError(
            f"perturbation {text!r}: {name} takes values {kind.values} ({kind.meaning}), "
            f"got LOW {low:g}"
        )
    return Perturbation(name, low, high)
