"""Propose expectations from a motion's name, for people to review (``motiontool expect --infer``).

A name is not a measurement: ``Forwards`` says which way, not how far, and Webots'
``TurnLeft10`` turns about 32 degrees. So only what the name says plainly is proposed; the first
rule that fits wins:

================================  =============================================================
name has                          proposal
================================  =============================================================
Stand/Get/Gen/Fast/Quick/Rise    ``upright`` at the end; start ``lying-front`` / ``lying-back``
+ Up (StandUp, GetUpFront,        from Front/Belly/Prone or Back/Supine; else decided by playing
GenUp, Genup, StandingUp)         the file from both (:mod:`motiontool.sim.infer_start`)
Fall / Dive [+ side]              ``fell``; with Left/Right/Forward/Front/Back also
                                  ``fall_direction=90±45`` (-90, 0, 180)
Kick / Shoot(ing) / Shot / Pass   ``no-fall`` (a direction word is the ball's, not a walk)
Turn + Left/Right [+N]            ``yaw=±N±15%`` (at least 5°) when N follows the turn word
                                  and is 1-360: ``Team5_TurnLeft60`` is 60; else the sign only,
                                  ``yaw>0`` / ``yaw<0``; ``upright``
Side / Step + Left/Right          ``dy_heading>=0.03`` / ``dy_heading<=-0.03``; ``upright``
Walk / Step [+ Back(ward)]        ``dx_heading>=0.03`` (back: ``<=-0.03``); ``upright`` (a
                                  number is not a distance)
Wave / Hand / Wipe / Salute /     ``upright``, ``feet-planted`` (upper body only: LeanForward
Bow / Head / Arm / Nod / Lean /   is no walk)
Bend / Look / Point(ing) /
Reach / Thumb(s) / (Good)bye
Backward(s)                       ``dx_heading<=-0.03``; ``upright``
Forward(s) / Fwd                  ``dx_heading>=0.03``; ``upright``
anything else                     ``upright``
a fixed-base robot (arm)          ``no-self-collision`` (it cannot fall or walk)
================================  =============================================================

``upright`` is the play report's fall detector (no fall, up at the end), not a tilt bound.

Across the names (:func:`propose_chains`): a ``_Start`` / ``_Loop`` / ``_Stop`` family
(``SideStepLeft_Start``, ``WalkLoop``) is a chain, as a controller plays it: the loop gets
``after`` its start, the stop ``after`` its loop (else its start).
"""

from __future__ import annotations

import itertools
import json
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from motiontool.sim.start import StartState

__all__ = [
    "FALL_DIRECTION_TOLERANCE_DEG",
    "MIN_PROGRESS_M",
    "TURN_TOLERANCE",
    "Inference",
    "infer",
    "propose_chains",
    "render_toml",
    "words",
]

TURN_TOLERANCE = 0.15
"""Relative tolerance of an inferred turn angle (``TurnLeft60`` -> ``yaw=60±9``), at least 5°."""

_TURN_MIN_TOLERANCE_DEG = 5.0
_MAX_TURN_DEG = 360

FALL_DIRECTION_TOLERANCE_DEG = 45.0
"""Tolerance of an inferred fall direction, degrees either side (``DiveLeft`` -> 45..135)."""

MIN_PROGRESS_M = 0.03
"""Least progress (m, along the start heading, or to its side) a walk or a side step must
make: more than a standing robot sways (the Webots arm motions move the torso < 0.01 m)."""

_ARMS = {"wave", "hand", "hands", "wipe", "salute", "bow", "head", "arm", "arms", "nod", "no"}
_ARMS |= {"lean", "bend", "look", "point", "pointing", "points", "reach"}
_ARMS |= {"thumb", "thumbs", "goodbye", "bye", "waving", "gesture"}
_UP_VERB = re.compile(r"(stand|get|gen|fast|quick|slow|rise)(t?ing)?")
"""A word that goes with ``up`` in a stand-up's name (StandUp, GettingUp, GenUp, FastUp)."""
_UP_WORDS = {"standup", "getup", "genup"}
_FALLS = {"fall", "falls", "falling", "dive", "dives", "diving"}
_KICKS = {"kick", "kicks", "kicking", "shoot", "shoots", "shooting", "shot", "shots", "pass"}
_KICKS |= {"passes"}
_FALL_SIDES = {
    "left": 90,
    "right": -90,
    "forward": 0,
    "forwards": 0,
    "front": 0,
    "back": 180,
    "backward": 180,
    "backwards": 180,
}
_SIDES = {"left", "right"}
_TURNS = {"turn", "turns", "turning"}
_WALKS = {"walk", "walks", "walking", "step", "steps"}
_BACKWARDS = {"back", "backward", "backwards"}
_WAYS = {False: "walks forwards", True: "walks backwards"}


@dataclass
class Inference:
    """What a motion's name suggests: a sidecar section, with notes for the reviewer.

    ``needs_start``: a stand-up whose name does not say front or back (the start is then to be
    found by playing the motion, or set by the reviewer). ``after``: the motion played before
    it, a chain (:func:`propose_chains`). ``details``: comment lines under its section (the
    members of an ensemble that disagree); ``fragile``: a decision played over an ensemble did
    not hold (:mod:`motiontool.sim.infer_start`).
    """

    name: str
    expect: list[str] = field(default_factory=list)
    start: StartState | None = None
    notes: list[str] = field(default_factory=list)
    needs_start: bool = False
    after: str | None = None
    details: list[str] = field(default_factory=list)
    fragile: bool = False


def words(name: str) -> list[str]:
    """``TurnLeft60`` -> ``turn left 60``; ``wave_right`` -> ``wave right``; lower case."""
    spaced = re.sub(r"([a-z])([A-Z])", r"\1 \2", name)
    spaced = re.sub(r"([A-Z]+)([A-Z][a-z])", r"\1 \2", spaced)
    spaced = re.sub(r"([A-Za-z])(\d)|(\d)([A-Za-z])", r"\1\3 \2\4", spaced)
    return [w.lower() for w in re.split(r"[^A-Za-z0-9]+", spaced) if w]


def _side(ws: Sequence[str]) -> int:
    return 1 if "left" in ws else -1 if "right" in ws else 0


def _is_stand_up(ws: list[str]) -> bool:
    pairs = itertools.pairwise(ws)
    return any(w in _UP_WORDS for w in ws) or any(
        _UP_VERB.fullmatch(a) is not None and b == "up" for a, b in pairs
    )


def _turn(ws: list[str]) -> tuple[int, int | None]:
    """(side: +1 left, -1 right, 0 none; the number attached to the turn word or None).

    The number is the first one after the turn word with only side words in between
    (``turn left 60``, ``turn 90 right``, ``left turn 45``): a team or version number elsewhere
    (``team 5 turn left 60``, ``v 2 turn right 30``) is not the angle."""
    i = next(k for k, w in enumerate(ws) if w in _TURNS)
    number = None
    for w in ws[i + 1 :]:
        if w.isdigit():
            number = int(w)
            break
        if w not in _SIDES:
            break
    return _side(ws[i : i + 3]) or _side(ws[max(0, i - 1) : i]), number


def _stand_up(out: Inference, ws: list[str]) -> None:
    out.expect = ["upright"]
    if {"front", "belly", "prone"} & set(ws):
        out.start = StartState.LYING_FRONT
    elif {"back", "supine"} & set(ws):
        out.start = StartState.LYING_BACK
    else:
        out.needs_start = True
        out.notes.append("the name does not say front or back: set start")
    out.notes.append("stands up: upright at the end")


def _fall(out: Inference, ws: list[str]) -> None:
    out.expect = ["fell"]
    sides = [w for w in ws if w in _FALL_SIDES]
    if sides:
        deg = _FALL_SIDES[sides[0]]
        out.expect.append(f"fall_direction={deg}±{FALL_DIRECTION_TOLERANCE_DEG:g}")
        out.notes.append(f"falls {sides[0]}: the fall is expected, to that side")
    else:
        out.notes.append("falls: the fall is expected (the name does not say which way)")


def _turn_proposal(out: Inference, side: int, angle: int | None) -> None:
    way = "left" if side > 0 else "right"
    if angle is not None and 1 <= angle <= _MAX_TURN_DEG:
        tol = max(_TURN_MIN_TOLERANCE_DEG, round(TURN_TOLERANCE * angle))
        out.expect = [f"yaw={side * angle}±{tol:g}", "upright"]
        note = f"turns {way} {angle} deg if {angle} is degrees: check"
        if angle < 30:
            note += " (Webots' TurnLeft10 turns about 32 deg)"
        out.notes.append(note)
    else:
        out.expect = ["yaw>0" if side > 0 else "yaw<0", "upright"]
        why = f"'{angle}' is not taken as degrees" if angle is not None else "no angle"
        out.notes.append(f"turns {way}; {why}: direction only")


def _progress(out: Inference, quantity: str, sign: int, what: str, numbers: bool) -> None:
    op = ">=" if sign > 0 else "<="
    out.expect = [f"{quantity}{op}{sign * MIN_PROGRESS_M:g}", "upright"]
    out.notes.append(what + ("; the number is not a distance" if numbers else ""))


def infer(name: str, *, floating_base: bool | None = None) -> Inference:
    """The expectations ``name`` (a motion file's stem) suggests (rules: the module docstring).

    Args:
        name: the motion's name, e.g. ``TurnLeft60``.
        floating_base: whether the robot is free-flying (False: an arm on a base, which gets
            ``no-self-collision`` only); None when not known (a bare name).
    """
    out = Inference(name)
    ws = words(name)
    has = set(ws)
    if floating_base is False:
        out.expect = ["no-self-collision"]
        out.notes.append("a fixed-base robot: add tracking_error<BOUND after a first run")
        return out
    numbers = any(w.isdigit() for w in ws)
    if _is_stand_up(ws):
        _stand_up(out, ws)
    elif _FALLS & has:
        _fall(out, ws)
    elif _KICKS & has:
        out.expect = ["no-fall"]
        ways = set(_FALL_SIDES) & has or "side" in has
        out.notes.append(
            "kicks: no fall" + ("; the direction is the ball's, not a walk" if ways else "")
        )
    elif _TURNS & has and _turn(ws)[0]:
        _turn_proposal(out, *_turn(ws))
    elif _side(ws) and ("side" in has or {"step", "steps"} & has):
        way = "left" if _side(ws) > 0 else "right"
        _progress(out, "dy_heading", _side(ws), f"steps to the {way}", numbers)
    elif _WALKS & has:
        back = bool(_BACKWARDS & has)
        _progress(out, "dx_heading", -1 if back else 1, _WAYS[back], numbers)
    elif _ARMS & has or "wipe" in "".join(ws):
        out.expect = ["upright", "feet-planted"]
        out.notes.append("upper body only: the feet stay where they are")
    elif (_BACKWARDS - {"back"}) & has:
        _progress(out, "dx_heading", -1, _WAYS[True], numbers)
    elif {"forward", "forwards", "fwd"} & has:
        _progress(out, "dx_heading", 1, _WAYS[False], numbers)
    else:
        out.expect = ["upright"]
        out.notes.append("nothing in the name: stays upright")
    return out


_PHASE = re.compile(r"^(?P<base>.*?[A-Za-z0-9])[_-]?(?P<phase>start|loop|stop)$", re.IGNORECASE)
_PHASE_NOTES = {"loop": "the loop of {base}", "stop": "the end of {base}"}


def propose_chains(inferences: Sequence[Inference]) -> None:
    """Set ``after`` of each ``_Loop`` / ``_Stop`` of a ``_Start`` / ``_Loop`` / ``_Stop``
    family among ``inferences`` (``SideStepLeft_Start``, ``WalkLoop``): a loop plays after its
    start, a stop after its loop, else its start; a note says so."""
    families: dict[str, dict[str, str]] = {}
    for inf in inferences:
        m = _PHASE.match(inf.name)
        if m:
            families.setdefault(m["base"], {})[m["phase"].lower()] = inf.name
    for inf in inferences:
        m = _PHASE.match(inf.name)
        if not m or m["phase"].lower() == "start":
            continue
        family = families[m["base"]]
        phase = m["phase"].lower()
        before = family.get("start") if phase == "loop" else family.get("loop", family.get("start"))
        if before is not None:
            inf.after = before
            what = _PHASE_NOTES[phase].format(base=m["base"])
            inf.notes.insert(0, f"{what}: played after {before}")


def _toml_key(name: str) -> str:
    return name if re.fullmatch(r"[A-Za-z0-9_-]+", name) else json.dumps(name, ensure_ascii=False)


def render_toml(
    inferences: Sequence[Inference],
    *,
    world: str | None = None,
    robot_node: str | None = None,
    header: Sequence[str] = (),
) -> str:
    """The inferences as a ``motions.toml`` (:mod:`motiontool.sim.sidecar`) to review: each
    played in ``world`` (a path from the sidecar's folder) by its ``robot_node`` when given;
    ``header``: more comment lines for the top (how the motions were played)."""
    lines = [
        "# motions.toml: expectations proposed from the motion names by `motiontool expect",
        "# --infer`. REVIEW EVERY LINE before you commit it: a name is not a measurement",
        "# (Webots' TurnLeft10 turns about 32 deg). Syntax: docs/play.md, 'Expectations'.",
        *(f"# {line}" for line in header),
    ]
    for inf in inferences:
        lines.append("")
        lines.append(f"[{_toml_key(inf.name)}]  # {'; '.join(inf.notes)}")
        lines += [f"# {line}" for line in inf.details]
        lines.append(
            "expect = [" + ", ".join(json.dumps(e, ensure_ascii=False) for e in inf.expect) + "]"
        )
        if inf.start is not None:
            lines.append(f'start = "{inf.start}"')
        if inf.after is not None:
            lines.append(f"after = {json.dumps(inf.after, ensure_ascii=False)}")
        if world is not None:
            lines.append(f"world = {json.dumps(world, ensure_ascii=False)}")
        if robot_node is not None:
            lines.append(f"robot-node = {json.dumps(robot_node, ensure_ascii=False)}")
    return "\n".join(lines) + "\n"
