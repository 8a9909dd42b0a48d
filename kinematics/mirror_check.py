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

from motiontool.kinematics.mirror import MirrorMap, mirror_map
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.fileio import is_stdin
from motiontool.motionfmt.reader import ReadResult, read_bytes

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


class UnmirroredCopy:
    """MT309 (info) for ``spec``: see the module docstring. A robot that cannot be mirrored
    joint by joint gets no note."""

    def __init__(self, spec: RobotSpec) -> None:
        self.spec = spec
        self._map: MirrorMap | None = None
        self._failed = False

    def _mirror(self) -> MirrorMap | None:
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
        if not path.is_file():
            return []
        siblings = sibling_paths(path)
        if not siblings:
            return []
        mirror = self._mirror()
        if mirror is None:
            return []
        for sibling in siblings:
            try:
                other = read_bytes(sibling.read_bytes(), str(sibling))
            except OSError:
                continue
            if not other.accepted:
                continue
            joints = unmirrored_joints(result, other, mirror)
            if joints is None:
                continue
            spans = result.header_spans()
            j = result.joints.index(joints[0])
            column, end = spans[j] if j < len(spans) else (1, None)
            signs = mirror.as_dict()
            shown = ", ".join(f"{name} (= {signs[name][0]} of {sibling.name})" for name in joints)
            return [
                Diagnostic(
                    code="MT309",
                    severity=Severity.INFO,
                    path=result.path,
                    line=1,
                    column=column,
                    message=(
                        f"looks like an unmirrored copy of {sibling.name}: {shown} "
                        "without the sign flip a left/right mirror needs"
                        f" ({self.spec.name}'s joint axes)"
                    ),
                    hint=(
                        f"'motiontool mirror {sibling.name} -o {path.name}' writes the true "
                        "mirror; if the motion is meant to be asymmetric, --ignore MT309"
                    ),
                    joint=joints[0],
                    end_column=end,
                )
            ]
        return []
