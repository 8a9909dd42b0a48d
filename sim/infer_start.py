"""The lying start a stand-up motion needs, found by playing it (``expect --infer``).

A stand-up whose name does not say front or back (``GetUp``, ``FastUp``) needs one of the two
lying starts, and its poses alone do not say which: a motion is written for one of them. So the
file is played from ``lying-front`` and from ``lying-back`` (:func:`motiontool.sim.play.play`,
the defaults of ``play``), and the rule is:

- it gets up (the fall detector: no fall, up at the end) from exactly one: that start;
- from both, or from neither: not decidable; the proposal says so and leaves ``start`` unset
  for the reviewer.

Without the simulator (the ``sim`` extra) nothing is played and the proposal says so too.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.sim.start import LYING_STARTS, StartState

if TYPE_CHECKING:
    from motiontool.kinematics.robots import RobotSpec
    from motiontool.sim.infer import Inference

__all__ = ["find_start"]


def _got_up(path: Path, robot: RobotSpec, start: StartState) -> bool:
    from motiontool.sim.play import PlayOptions, play

    base = play([path], robot=robot, options=PlayOptions(start=start)).base
    return base is not None and not base.fell and base.upright_at_end


def find_start(inference: Inference, path: Path, robot: RobotSpec) -> None:
    """Set ``inference.start`` for a stand-up that needs one (``needs_start``) by playing
    ``path`` on ``robot`` from both lying starts, with a note saying what was found."""
    if not inference.needs_start:
        return
    inference.notes = [n for n in inference.notes if "does not say front or back" not in n]
    try:
        up = [start for start in LYING_STARTS if _got_up(path, robot, start)]
    except ImportError as exc:
        inference.notes.insert(
            0, f"the name does not say front or back and it cannot be played ({exc}): set start"
        )
        return
    except MotionToolError as exc:
        inference.notes.insert(0, f"the name does not say front or back; playing it: {exc}")
        return
    if len(up) == 1:
        inference.start = up[0]
        other = next(s for s in LYING_STARTS if s != up[0])
        note = f"played from both lying starts: gets up from {up[0]}, not from {other}"
    else:
        which = "both" if up else "neither"
        note = (
            f"the name does not say front or back, and played it gets up from {which} of "
            "lying-front and lying-back: not decidable, set start"
        )
    inference.notes.insert(0, note)
