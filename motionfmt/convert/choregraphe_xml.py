"""Choregraphe timelines: a behaviour's ``.xar`` (or the ``.anim`` of its older projects) holds,
in a ``Timeline`` (its ``fps``), an ``ActuatorList`` of ``ActuatorCurve`` s (``actuator``,
``unit``: 0 degrees, 1 a fraction, absent or -1 degrees but for the hands; ``mute``), each of
``Key`` s (``frame``, ``value``) with their ``Tangent`` s (``side`` left or right,
``interpType`` bezier, linear, constant or bezier auto, ``abscissaParam`` in frames,
``ordinateParam`` in the curve's unit): the curves Choregraphe sends to
``angleInterpolationBezier`` (time = frame / fps, angles in rad), read as :mod:`.choregraphe`
says.

Read with the standard library's expat parser, element by element, and nothing else: no
entity is declared or expanded (a document declaring one is refused), nothing is fetched, no
script of the behaviour is run. A ``.pml`` is a project: it lists its behaviours' ``.xar``
files, which it names in its one-line refusal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING
from xml.parsers import expat

from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.motionfmt.convert.base import Imported, ImportOptions
from motiontool.motionfmt.convert.choregraphe import (
    Curve,
    auto_handles,
    bezier_handle,
    curves_motion,
    refuse_handles,
)

if TYPE_CHECKING:
    from motiontool.motionfmt.convert.naoqi_curve import Key

__all__ = ["read_timeline"]

_TYPES = {
    "bezier": "bezier",
    "bezier sym": "bezier",
    "bezier smooth": "bezier",
    "bezier harsh": "bezier",
    "bezier auto": "auto",
    "linear": "linear",
    "none": "linear",
    "constant": "constant",
    "piecewise constant": "constant",
}
"""Choregraphe's ``interpType`` names (with the older ones it still reads) -> what they do."""


@dataclass
class _Key:
    frame: int
    value: float
    line: int
    tangents: dict[str, tuple[str, float, float]] = field(default_factory=dict)


@dataclass
class _Curve:
    actuator: str
    scale: float
    line: int
    fps: float
    timeline: int
    keys: dict[int, _Key] = field(default_factory=dict)


class _Timeline:
    """Expat's handlers: the curves of every timeline, as they come."""

    def __init__(self, parser: expat.XMLParserType, path: str) -> None:
        self.parser, self.path = parser, path
        self.fps: list[tuple[int, float | None]] = []  # (number, fps) of the open timelines
        self.opened = 0
        self.curves: list[_Curve] = []
        self.behaviours: list[str] = []
        self._curve: _Curve | None = None
        self._key: _Key | None = None

    def fail(self, message: str) -> MotionSyntaxError:
        p = self.parser
        return MotionSyntaxError(message, self.path, p.CurrentLineNumber, p.CurrentColumnNumber + 1)

    def number(self, attrs: dict[str, str], name: str, element: str) -> float:
        text = attrs.get(name)
        try:
            value = float(text) if text is not None else math.nan
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            raise self.fail(f"{element}: {name}={text!r}: expected a finite number")
        return value

    def start(self, name: str, attrs: dict[str, str]) -> None:
        tag = name.rsplit(":", 1)[-1]
        if tag in ("Timeline", "Animation"):
            fps = self.number(attrs, "fps", tag) if "fps" in attrs else None
            if fps is not None and fps <= 0:
                raise self.fail(f"{tag}: fps={attrs['fps']!r}: expected a number > 0")
            self.opened += 1
            self.fps.append((self.opened, fps))
        elif tag == "BehaviorDescription":
            self.behaviours.append("/".join(x for x in (attrs.get("src"), attrs.get("xar")) if x))
        elif tag == "ActuatorCurve":
            self.start_curve(attrs)
        elif tag == "Key" and self._curve is not None:
            frame = self.number(attrs, "frame", "Key")
            if frame != int(frame):
                raise self.fail(f"Key: frame={attrs['frame']!r}: expected a whole frame number")
            value = self.number(attrs, "value", "Key")
            self._key = _Key(int(frame), value, self.parser.CurrentLineNumber)
        elif tag == "Tangent" and self._key is not None:
            self.tangent(attrs)

    def start_curve(self, attrs: dict[str, str]) -> None:
        fps = next((f for _, f in reversed(self.fps) if f is not None), None)
        if fps is None or not self.fps:
            raise self.fail("ActuatorCurve outside a Timeline that gives its fps")
        actuator = attrs.get("actuator", "")
        if not actuator:
            raise self.fail("ActuatorCurve: no actuator named")
        unit = attrs.get("unit", "-1")
        if unit not in ("-1", "0", "1", "None"):
            raise self.fail(f"ActuatorCurve {actuator}: unit={unit!r}: expected 0, 1 or -1")
        hand = actuator in ("LHand", "RHand")
        degrees = unit == "0" or (unit in ("-1", "None") and not hand)
        scale = math.pi / 180.0 if degrees else 1.0
        line = self.parser.CurrentLineNumber
        curve = _Curve(actuator, scale, line, fps, self.fps[-1][0])
        if attrs.get("mute", "0") != "1":  # Choregraphe does not play a muted curve
            self.curves.append(curve)
        self._curve = curve

    def tangent(self, attrs: dict[str, str]) -> None:
        if self._key is None:
            return
        side, kind = attrs.get("side"), attrs.get("interpType")
        if side not in ("left", "right"):
            raise self.fail(f"Tangent: side={side!r}: expected 'left' or 'right'")
        if kind not in _TYPES:
            raise self.fail(f"Tangent: interpType={kind!r}: expected one of {', '.join(_TYPES)}")
        dx = self.number(attrs, "abscissaParam", "Tangent") if _TYPES[kind] == "bezier" else 0.0
        dy = self.number(attrs, "ordinateParam", "Tangent") if _TYPES[kind] == "bezier" else 0.0
        self._key.tangents[side] = (_TYPES[kind], dx, dy)

    def end(self, name: str) -> None:
        tag = name.rsplit(":", 1)[-1]
        if tag == "Key" and self._key is not None and self._curve is not None:
            if self._key.frame in self._curve.keys:
                raise self.fail(f"{self._curve.actuator}: a second key at frame {self._key.frame}")
            self._curve.keys[self._key.frame] = self._key
            self._key = None
        elif tag == "ActuatorCurve":
            self._curve = None
        elif tag in ("Timeline", "Animation"):
            self.fps.pop()

    def refuse_entity(self, *args: object) -> None:
        raise self.fail("an entity declaration: not read (a timeline declares none)")


def _parsed(data: bytes, path: str) -> _Timeline:
    parser = expat.ParserCreate()
    found = _Timeline(parser, path)
    parser.StartElementHandler = found.start
    parser.EndElementHandler = found.end
    parser.EntityDeclHandler = found.refuse_entity
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    try:
        parser.Parse(data, True)
    except expat.ExpatError as e:
        message = f"not well-formed XML: {expat.ErrorString(e.code)}"
        raise MotionSyntaxError(message, path, e.lineno, e.offset + 1) from None
    return found


def _curve(raw: _Curve, path: str) -> Curve:
    """The curve of a timeline's keys, handles resolved (see :mod:`.choregraphe`)."""
    frames = sorted(raw.keys)
    t = [f / raw.fps for f in frames]
    a = [raw.keys[f].value * raw.scale for f in frames]
    keys: list[Key] = []
    hold: list[bool] = []
    for i, f in enumerate(frames):
        tangents = raw.keys[f].tangents
        auto = auto_handles(t, a, i)
        handles = []
        for k, side in enumerate(("left", "right")):
            kind, dx, dy = tangents.get(side, ("auto", 0.0, 0.0))
            if kind == "bezier":
                handles.append(bezier_handle(dx / raw.fps, dy * raw.scale))
            elif kind == "linear":
                j = i - 1 if side == "left" else i + 1
                inside = 0 <= j < len(t)
                dt = (t[j] - t[i]) / 3.0 if inside else 0.0
                handles.append(bezier_handle(dt, (a[j] - a[i]) / 3.0 if inside else 0.0))
            else:  # auto, and constant (whose segment holds)
                handles.append(bezier_handle(*auto[k]))
        keys.append((a[i], handles[0], handles[1]))
        hold.append(tangents.get("right", ("auto",))[0] == "constant")
    curve = Curve(raw.actuator, tuple(t), tuple(keys), tuple(hold[:-1]), raw.line)
    refuse_handles(curve, f"{path}:{raw.line}")
    return curve


def read_timeline(data: bytes, path: str, options: ImportOptions | None = None) -> Imported:
    """The motion of a Choregraphe timeline (see the module).

    Raises:
        MotionSyntaxError: not well-formed XML, or an element of a timeline that is not what
            Choregraphe writes (its line).
        MotionToolError: no timeline, or more than one with curves; handles outside their
            segment.
    """
    found = _parsed(data, path)
    if not found.curves:
        lists = (
            f": it lists {', '.join(found.behaviours)}; convert that" if found.behaviours else ""
        )
        raise MotionToolError(f"'{path}' holds no timeline with a joint curve{lists}")
    timelines = sorted({c.timeline for c in found.curves})
    if len(timelines) > 1:
        first = [next(c.line for c in found.curves if c.timeline == n) for n in timelines]
        raise MotionToolError(
            f"'{path}' holds {len(timelines)} timelines with joint curves (their first curves "
            f"at lines {', '.join(map(str, first))}); motiontool reads a file with one"
        )
    curves = [_curve(raw, path) for raw in found.curves if raw.keys]
    fps = found.curves[0].fps
    what = f"a Choregraphe timeline at {fps:g} fps"
    notes = []
    if any(len(k.tangents) < 2 for raw in found.curves for k in raw.keys.values()):
        notes.append("keys without tangents: Choregraphe's automatic Bézier handles")
    return curves_motion(curves, path, options or ImportOptions(), what, notes)
