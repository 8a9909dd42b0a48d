"""MT309: a ``*Left*`` / ``*Right*`` motion that looks like an unmirrored copy of its sibling.

Motion libraries keep a left and a right version of a gesture (``HandHighLeft.motion``,
``HandHighRight.motion``). Written by copying one and renaming its columns, the copy keeps
the values of the joints whose mirror image turns the other way (roll and yaw joints), and the
robot moves its other arm the wrong way, often past a limit (Webots' ``HandWaveLeft`` is
``HandWave`` so copied).

For a file whose name has a side word (``Left``/``Right``, any case), the siblings are the
files in the same folder named with the other side (``HandHighRight``) or without the side
(``HandWave`` for ``HandWaveLeft``). The note is given when a sibling has the same pose times,
and each joint that both command (partners by :func:`~motiontool.kinematics.mirror.mirror_map`)
holds either the mirrored values of the sibling's partner column or those values without the
sign flip, and at least one holds them without the flip where the flip changes something.
Exact comparison: a copy is a copy to the last digit; motions that merely look alike do not
get the note.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.kinematics.checks._table import WordedCheck, header_diagnostic
from motiontool.kinematics.checks.wording import PLAIN_WORDING, Wording
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.diagnostics import UNMIRRORED_COPY, Diagnostic, Severity
from motiontool.motionfmt.fileio import is_stdin
from motiontool.motionfmt.reader import ReadResult, read_bytes

if TYPE_CHECKING:
    from motiontool.kinematics.mirror import MirrorMap

__all__ = ["UnmirroredCopy", "sibling_paths", "unmirrored_joints"]

_SIDE = re.compile(r"(left|right)", re.IGNORECASE)
_OTHER = {"left": "right", "right": "left"}


def _swap_case(word: str, like: str) -> str:
    if like.isupper():
        return word.upper()
    if like[:1].isupper():
        return word.capitalize()
    return word


def sibling_paths(path: Path) -> list[Path]:
    """The files in ``path``'s folder that may be its mirror: the side word swapped, then the
    side word removed (``HandWaveLeft.motion`` -> ``HandWaveRight.motion``,
    ``HandWave.motion``); only those that exist."""
    stem = path.stem
    out = []
    for m in _SIDE.finditer(stem):
        side = m.group(1)
        other = _swap_case(_OTHER[side.lower()], side)
        for name in (
            stem[: m.start()] + other + stem[m.end() :],
            stem[: m.start()] + stem[m.end() :],
        ):
            candidate = path.with_name(name + path.suffix)
            if name and candidate != path and candidate.is_file() and candidate not in out:
                out.append(candidate)
    return out


def unmirrored_joints(file: ReadResult, sibling: ReadResult, mirror: MirrorMap) -> list[str] | None:
    """The joints of ``file`` that hold ``sibling``'s partner values without the mirror's sign
    flip, or None when ``file`` is not a (partly unmirrored) mirror copy of ``sibling``."""
    import numpy as np

    a, b = file.motion, sibling.motion
    if not np.array_equal(a.times_ms, b.times_ms):
        return None
    signs = mirror.as_dict()
    b_col = {name: j for j, name in enumerate(b.joints)}
    compared = 0
    unflipped = []
    for j, name in enumerate(a.joints):
        if name not in signs or a.joints.index(name) != j:
            continue
        partner, sign = signs[name]
        if partner not in b_col:
            continue
        k = b_col[partner]
        mine, theirs = a.values[:, j], b.values[:, k]
        if not np.array_equal(a.commanded[:, j], b.commanded[:, k]):
            return None
        compared += 1
        mirrored = np.array_equal(mine, sign * theirs + 0.0, equal_nan=True)
        copied = np.array_equal(mine, theirs, equal_nan=True)
        if not (mirrored or copied):
            return None
        if copied and not mirrored:
            unflipped.append(name)
    return unflipped if compared and unflipped else None


class UnmirroredCopy(WordedCheck):
    """MT309 (info) for ``spec``: see the module docstring. A robot that cannot be mirrored
    joint by joint gets no note.

    The hint says how to write the true mirror and how to leave the note out, in the front
    end's words (:class:`~motiontool.kinematics.checks.wording.Wording`).
    """

    def __init__(self, spec: RobotSpec, wording: Wording = PLAIN_WORDING) -> None:
        super().__init__(spec, wording)
        self._map: MirrorMap | None = None
        self._failed = False

    def _mirror(self) -> MirrorMap | None:
        """The robot's mirror map, derived once, where a file has a sibling to compare with:
        a file without one imports no mirror code."""
        from motiontool.kinematics.mirror import mirror_map

        if self._map is None and not self._failed:
            try:
                self._map = mirror_map(self.spec)
            except MotionToolError:
                self._failed = True
        return self._map

    def __call__(self, result: ReadResult) -> list[Diagnostic]:
        if is_stdin(result.path) or not _SIDE.search(Path(result.path).stem):
            return []
        path = Path(result.path)
        siblings = sibling_paths(path) if path.is_file() else []
        mirror = self._mirror() if siblings else None
        if mirror is None:
            return []
        for sibling in siblings:
            other = _read(sibling)
            joints = None if other is None else unmirrored_joints(result, other, mirror)
            if joints is not None:
                return [self._note(result, sibling, joints, mirror)]
        return []

    def _note(
        self, result: ReadResult, sibling: Path, joints: list[str], mirror: MirrorMap
    ) -> Diagnostic:
        """MT309 on the header token of the first of ``joints``, the unflipped copies of
        ``sibling``'s partner columns."""
        signs = mirror.as_dict()
        shown = ", ".join(f"{name} (= {signs[name][0]} of {sibling.name})" for name in joints)
        return header_diagnostic(
            result,
            result.joints.index(joints[0]),
            UNMIRRORED_COPY,
            Severity.INFO,
            f"looks like an unmirrored copy of {sibling.name}: {shown} without the sign flip a "
            f"left/right mirror needs ({self.spec.name}'s joint axes)",
            self._hint(sibling.name, Path(result.path).name),
        )

    def _hint(self, sibling: str, name: str) -> str:
        """How to write the true mirror of ``sibling`` into ``name``, or to leave MT309 out."""
        command = self.wording.mirror(sibling, name)
        if command:
            write = f"'{command}' writes the true mirror"
        else:
            write = f"the left/right mirror of {sibling} is the true one"
        ignore = self.wording.ignore(UNMIRRORED_COPY)
        return f"{write}; if the motion is meant to be asymmetric, {ignore}"


def _read(path: Path) -> ReadResult | None:
    """``path`` as Webots reads it; None if it cannot be read or Webots rejects it."""
    try:
        other = read_bytes(path.read_bytes(), str(path))
    except OSError:
        return None
    return other if other.accepted else None
