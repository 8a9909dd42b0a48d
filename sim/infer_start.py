"""The lying start a stand-up motion needs, found by playing it (``expect --infer``).

A stand-up whose name does not say front or back (``GetUp``, ``FastUp``) needs one of the two
lying starts, and its poses alone do not say which: a motion is written for one of them. So the
file is played from ``lying-front`` and from ``lying-back`` (a :data:`Probe`: by default
:func:`motiontool.sim.play.play` with the defaults of ``play``; the caller's may play in a
Webots world, from a start pose), and the rule is:

- it gets up (the fall detector: no fall, up at the end) from exactly one: that start;
- from both, or from neither: not decidable; the proposal says so and leaves ``start`` unset
  for the reviewer.

Where the probe replays each start over an ensemble (:mod:`motiontool.sim.robustness`: its
:attr:`ProbeResult.replay`), the start is proposed only where the decision holds: every member
of the start it gets up from gets up, no member of the other does. Else the decision is
*fragile*: no start is proposed, the note says how many members of which start disagree, each
of them is a comment line of its own (:attr:`~motiontool.sim.infer.Inference.details`) and
:attr:`~motiontool.sim.infer.Inference.fragile` is set.

Without the simulator (the ``sim`` extra) nothing is played and the proposal says so too.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.sim.start import LYING_STARTS, StartState

if TYPE_CHECKING:
    from motiontool.kinematics.robots import RobotSpec
    from motiontool.sim.infer import Inference
    from motiontool.sim.robustness import Robustness

__all__ = ["UPRIGHT", "Probe", "ProbeResult", "find_start", "play_probe"]

UPRIGHT = "upright"
"""The expectation a probe judges: no fall, up at the end (the fall detector)."""


def _no_replay() -> Robustness | None:
    return None


@dataclass(frozen=True)
class ProbeResult:
    """A stand-up played from one lying start.

    Attributes:
        up: whether it got up (:data:`UPRIGHT` passed).
        replay: the run replayed over an ensemble, judged as it was (its verdicts include
            :data:`UPRIGHT`); called only where a start is to be proposed; returns None when
            there is no ensemble.
    """

    up: bool
    replay: Callable[[], Robustness | None] = _no_replay


Probe = Callable[[Path, "RobotSpec", StartState], ProbeResult]
"""Plays the motion file on the robot from a lying start (raises MotionToolError when it
cannot be played, ImportError without the simulator)."""


def play_probe(path: Path, robot: RobotSpec, start: StartState) -> ProbeResult:
    """The default :data:`Probe`: ``play``'s defaults, no world, no ensemble."""
    from motiontool.sim.play import PlayOptions, play

    base = play([path], robot=robot, options=PlayOptions(start=start)).base
    return ProbeResult(base is not None and not base.fell and base.upright_at_end)


def find_start(
    inference: Inference, path: Path, robot: RobotSpec, probe: Probe = play_probe
) -> None:
    """Set ``inference.start`` for a stand-up that needs one (``needs_start``) by playing
    ``path`` on ``robot`` from both lying starts with ``probe``, with a note saying what was
    found (module docstring: a fragile decision proposes no start)."""
    if not inference.needs_start:
        return
    inference.notes = [n for n in inference.notes if "does not say front or back" not in n]
    try:
        results = {start: probe(path, robot, start) for start in LYING_STARTS}
    except ImportError as exc:
        inference.notes.insert(
            0, f"the name does not say front or back and it cannot be played ({exc}): set start"
        )
        return
    except MotionToolError as exc:
        inference.notes.insert(0, f"the name does not say front or back; playing it: {exc}")
        return
    up = [start for start, result in results.items() if result.up]
    if len(up) != 1:
        which = "both" if up else "neither"
        inference.notes.insert(
            0,
            f"the name does not say front or back, and played it gets up from {which} of "
            "lying-front and lying-back: not decidable, set start",
        )
        return
    other = next(s for s in LYING_STARTS if s != up[0])
    note = f"played from both lying starts: gets up from {up[0]}, not from {other}"
    inference.notes.insert(0, note + _replayed(inference, results))
    if not inference.fragile:
        inference.start = up[0]


def _replayed(inference: Inference, results: dict[StartState, ProbeResult]) -> str:
    """Each start replayed over its ensemble: ``""`` without one, else what the note adds
    (holds, or fragile: how many members of which start disagree, each a detail line, and
    ``inference.fragile`` set)."""
    ensembles = {start: result.replay() for start, result in results.items()}
    counted, members, seed = [], 0, 0
    for start, ensemble in ensembles.items():
        if ensemble is None:
            continue
        verdict = next(v for v in ensemble.verdicts if v.name == UPRIGHT)
        members, seed = ensemble.members, ensemble.seed
        if verdict.disagree:
            counted.append(f"{len(verdict.disagree)} of {members} members from {start}")
        for d in verdict.disagree:
            values = ", ".join(f"{k} {v:.3g}" for k, v in d.values.items())
            what = "gets up" if d.passed else d.why
            inference.details.append(
                f"disagrees: from {start}, member #{d.sample} ({values}): {what}"
            )
    if not members:
        return ""
    if not counted:
        return f"; holds over an ensemble of {members} members (seed {seed})"
    inference.fragile = True
    disagree = " and ".join(counted)
    return f", but fragile over an ensemble (seed {seed}): {disagree} disagree: set start"
