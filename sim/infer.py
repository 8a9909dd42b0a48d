"""Propose expectations from a motion's name, for people to review (``motiontool expect --infer``).

A name is not a measurement: ``Forwards`` says which way, not how far, and Webots'
``TurnLeft10`` turns about 32 degrees. So only what the name says plainly is proposed:

==============================  ===============================================================
name has                        proposal
==============================  ===============================================================
StandUp / GetUp (+Front/Back)   ``upright`` at the end; start ``lying-front`` / ``lying-back``
Fall                            ``fell``
Turn + Left/Right [+N]          ``yaw=±N±15%`` when N is a plausible angle (30-360, a multiple
                                of 5), else only the sign, ``yaw>0`` / ``yaw<0``; ``upright``
Forward(s) / Backward(s)        ``dx>0`` / ``dx<0``; ``upright`` (a number is not a distance)
SideStep / Side + Left/Right    ``dy>0`` / ``dy<0``; ``upright``
Wave / Hand / Wipe / Salute /   ``upright``, ``feet-planted`` (arms and head only)
Bow / Head / Arm / Nod
anything else                   ``upright``
a fixed-base robot (arm)        ``no-self-collision`` (it cannot fall or walk)
==============================  ===============================================================
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

__all__ = ["TURN_TOLERANCE", "Inference", "infer", "render_toml", "words"]

TURN_TOLERANCE = 0.15
"""Relative tolerance of an inferred turn angle (``TurnLeft60`` -> ``yaw=60±9``), at least 5°."""

_ARMS = {"wave", "hand", "hands", "wipe", "salute", "bow", "head", "arm", "arms", "nod", "no"}


@dataclass
class Inference:
    """What a motion's name suggests: a sidecar section, with notes for the reviewer."""

    name: str
    expect: list[str] = field(default_factory=list)
    start: str | None = None
    notes: list[str] = field(default_factory=list)


def words(name: str) -> list[str]:
    """``TurnLeft60`` -> ``turn left 60``; ``wave_right`` -> ``wave right``; lower case."""
    spaced = re.sub(r"([a-z])([A-Z])", r"\1 \2", name)
    spaced = re.sub(r"([A-Z]+)([A-Z][a-z])", r"\1 \2", spaced)
    spaced = re.sub(r"([A-Za-z])(\d)|(\d)([A-Za-z])", r"\1\3 \2\4", spaced)
    return [w.lower() for w in re.split(r"[^A-Za-z0-9]+", spaced) if w]


def _side(ws: list[str]) -> int:
    return 1 if "left" in ws else -1 if "right" in ws else 0


def infer(name: str, *, floating_base: bool | None = None) -> Inference:
    """The expectations ``name`` (a motion file's stem) suggests.

    Args:
        name: the motion's name, e.g. ``TurnLeft60``.
        floating_base: whether the robot is free-flying (False: an arm on a base, which gets
            ``no-self-collision`` only); None when not known (a bare name).
    """
    out = Inference(name)
    ws = words(name)
    joined = "".join(ws)
    if floating_base is False:
        out.expect = ["no-self-collision"]
        out.notes.append("a fixed-base robot: add tracking_error<BOUND after a first run")
        return out
    numbers = [int(w) for w in ws if w.isdigit()]
    if "standup" in joined or "getup" in joined:
        out.expect = ["upright"]
        if "front" in ws or "belly" in ws or "prone" in ws:
            out.start = "lying-front"
        elif "back" in ws or "supine" in ws:
            out.start = "lying-back"
        else:
            out.notes.append("the name does not say front or back: set start")
        out.notes.append("stands up: upright at the end")
    elif "fall" in ws or "falls" in ws:
        out.expect = ["fell"]
        out.notes.append("falls: the fall is expected")
    elif "turn" in ws and _side(ws):
        side = _side(ws)
        angle = numbers[0] if numbers else None
        if angle is not None and 30 <= angle <= 360 and angle % 5 == 0:
            tol = max(5.0, round(TURN_TOLERANCE * angle))
            out.expect = [f"yaw={side * angle}±{tol:g}", "upright"]
            out.notes.append(
                f"turns {'left' if side > 0 else 'right'} {angle} deg if {angle} is degrees: check"
            )
        else:
            out.expect = ["yaw>0" if side > 0 else "yaw<0", "upright"]
            why = f"'{angle}' is not taken as degrees" if angle is not None else "no angle"
            out.notes.append(f"turns {'left' if side > 0 else 'right'}; {why}: direction only")
    elif "side" in ws and _side(ws):
        out.expect = ["dy>0" if _side(ws) > 0 else "dy<0", "upright"]
        out.notes.append(f"steps to the {'left' if _side(ws) > 0 else 'right'}")
    elif {"forward", "forwards", "fwd"} & set(ws):
        out.expect = ["dx>0", "upright"]
        out.notes.append("walks forwards" + ("; the number is not a distance" if numbers else ""))
    elif {"backward", "backwards"} & set(ws):
        out.expect = ["dx<0", "upright"]
        out.notes.append("walks backwards" + ("; the number is not a distance" if numbers else ""))
    elif _ARMS & set(ws) or "wipe" in joined:
        out.expect = ["upright", "feet-planted"]
        out.notes.append("upper body only: the feet stay where they are")
    else:
        out.expect = ["upright"]
        out.notes.append("nothing in the name: stays upright")
    return out


def _toml_key(name: str) -> str:
    return name if re.fullmatch(r"[A-Za-z0-9_-]+", name) else json.dumps(name, ensure_ascii=False)


def render_toml(inferences: Sequence[Inference]) -> str:
    """The inferences as a ``motions.toml`` (:mod:`motiontool.sim.sidecar`) to review."""
    lines = [
        "# motions.toml: expectations proposed from the motion names by `motiontool expect",
        "# --infer`. REVIEW EVERY LINE before you commit it: a name is not a measurement",
        "# (Webots' TurnLeft10 turns about 32 deg). Syntax: README, 'Expectations'.",
    ]
    for inf in inferences:
        lines.append("")
        lines.append(f"[{_toml_key(inf.name)}]  # {'; '.join(inf.notes)}")
        lines.append(
            "expect = [" + ", ".join(json.dumps(e, ensure_ascii=False) for e in inf.expect) + "]"
        )
        if inf.start is not None:
            lines.append(f'start = "{inf.start}"')
    return "\n".join(lines) + "\n"
