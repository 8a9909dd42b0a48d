"""The start states of a run, one home for their names: ``play --start``, a sidecar's ``start``,
``expect --infer``, the play report and the MuJoCo scene all use :class:`StartState`."""

from __future__ import annotations

import enum

from motiontool.errors import MotionToolError

__all__ = ["LYING_STARTS", "StartState"]


class StartState(enum.StrEnum):
    """How a run starts: ``standing`` (zero pose, upright), ``lying-front`` (face down) or
    ``lying-back`` (face up). Lying starts need a free-flying robot."""

    STANDING = "standing"
    LYING_FRONT = "lying-front"
    LYING_BACK = "lying-back"

    @property
    def lying(self) -> bool:
        """Whether the robot starts on the floor."""
        return self is not StartState.STANDING

    @classmethod
    def parse(cls, text: str) -> StartState:
        """The start state spelt ``text``.

        Raises:
            MotionToolError: ``start 'sitting': choose standing, lying-front, lying-back``.
        """
        try:
            return cls(text)
        except ValueError:
            raise MotionToolError(f"start {text!r}: choose {', '.join(cls)}") from None


LYING_STARTS = (StartState.LYING_FRONT, StartState.LYING_BACK)
"""The lying starts, face down first."""
