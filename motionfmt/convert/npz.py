"""NumPy ``.npz``: the motion's arrays, for analysis and for other tools.

Arrays: ``times_ms`` int64 (P,), ms; ``names`` str (J,); ``positions`` float64 (P, J), rad (m
for linear joints), NaN where the cell is ``*``; ``commanded`` bool (P, J), False for ``*``;
``pose_names`` str (P,), optional on reading; ``robot_check`` str (0-D), written: the robot
the export was checked against, or ``unchecked``. Saved without pickles and read without them
(``allow_pickle=False``): a file cannot run code. ``motion -> npz -> motion`` keeps Webots'
command stream bit-identical (the doubles are stored as they are).
"""

from __future__ import annotations

import io
import zipfile
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionToolError
from motiontool.motionfmt.convert.base import (
    Exported,
    ExportOptions,
    Imported,
    ImportOptions,
    robot_check,
)
from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.writer import check_name, pose_name

if TYPE_CHECKING:
    from motiontool.motionfmt.motion import Motion

__all__ = ["ARRAYS", "read_npz", "write_npz"]

ARRAYS = ("times_ms", "names", "positions", "commanded")
"""The arrays every ``.npz`` motion has (``pose_names`` is optional)."""


def write_npz(motion: Motion, options: ExportOptions) -> Exported:
    """``motion`` as an uncompressed ``.npz`` (a ``nan`` or ``inf`` command is refused, as
    every writer of motions refuses it)."""
    import numpy as np

    refuse_non_finite(motion)
    out = io.BytesIO()
    np.savez(
        out,
        times_ms=motion.times_ms,
        names=np.array(motion.joints, dtype=np.str_),
        positions=motion.values,
        commanded=motion.commanded,
        pose_names=np.array(list(motion.pose_names), dtype=np.str_),
        robot_check=np.array(robot_check(options), dtype=np.str_),
    )
    detail = f"{motion.n_joints} joints, arrays {', '.join(ARRAYS)}, pose_names, robot_check"
    return Exported(out.getvalue(), motion.n_poses, detail)


_ZIP = b"PK\x03\x04"
"""How a zip archive, and so an ``.npz``, begins (an empty archive: ``PK\x05\x06``)."""
_NPY = b"\x93NUMPY"
"""How one ``.npy`` array begins."""


def _load(data: bytes, path: str) -> dict[str, Any]:
    """The arrays of ``data``; what is not a zip is said so before numpy reads it (numpy takes
    anything else for a pickle, and says it holds pickled data)."""
    import numpy as np

    if data.startswith(_NPY):
        reason = "one .npy array, not an .npz (a zip of .npy arrays)"
        raise MotionToolError(f"cannot read '{path}' as a .npz file: {reason}")
    if not data.startswith((_ZIP, b"PK\x05\x06")):
        reason = "not a zip archive (an .npz is a zip of .npy arrays)"
        raise MotionToolError(f"cannot read '{path}' as a .npz file: {reason}")
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as npz:
            return {name: npz[name] for name in npz.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise MotionToolError(f"cannot read '{path}' as a .npz file: {exc}") from exc


def _array(arrays: dict[str, Any], name: str, kind: str, ndim: int, path: str) -> Any:
    """The array ``name``, of dtype kind ``kind`` (numpy's one-letter code) and ``ndim``."""
    if name not in arrays:
        raise MotionToolError(
            f"'{path}' has no array '{name}'; a motion .npz has {', '.join(ARRAYS)}"
        )
    a = arrays[name]
    kinds = {"i": "integers", "U": "strings", "f": "floats", "b": "booleans"}
    if a.dtype.kind != kind or a.ndim != ndim:
        raise MotionToolError(
            f"'{path}': array '{name}' must be {ndim}-D {kinds[kind]}, got {a.ndim}-D {a.dtype}"
        )
    return a


def _check_shapes(arrays: dict[str, Any], path: str) -> None:
    import numpy as np

    times, names = arrays["times_ms"], arrays["names"]
    shape = (times.shape[0], names.shape[0])
    for name in ("positions", "commanded"):
        if arrays[name].shape != shape:
            raise MotionToolError(
                f"'{path}': array '{name}' has shape {arrays[name].shape}, expected {shape} "
                "(poses, joints)"
            )
    if shape[0] == 0 or shape[1] == 0:
        raise MotionToolError(f"'{path}': a motion needs at least one pose and one joint")
    if times[0] < 0 or times[-1] > INT_MAX or np.any(np.diff(times) <= 0):
        raise MotionToolError(
            f"'{path}': times_ms must strictly increase, within [0, {INT_MAX}] ms"
        )
    positions, commanded = arrays["positions"], arrays["commanded"]
    bad = np.argwhere(commanded & ~np.isfinite(positions))
    if bad.shape[0]:
        p, j = (int(x) for x in bad[0])
        raise MotionToolError(
            f"'{path}': {names[j]} at {int(times[p])} ms is commanded but not a finite number"
        )


def read_npz(data: bytes, path: str, options: ImportOptions | None = None) -> Imported:
    """A ``.npz`` motion (pose names from ``pose_names``, else ``Pose<ms>ms``); raises
    :class:`MotionToolError` naming the array at fault."""
    import numpy as np

    from motiontool.motionfmt.motion import Motion

    arrays = _load(data, path)
    for name, kind, ndim in (
        ("times_ms", "i", 1),
        ("names", "U", 1),
        ("positions", "f", 2),
        ("commanded", "b", 2),
    ):
        _array(arrays, name, kind, ndim, path)
    _check_shapes(arrays, path)
    times = arrays["times_ms"].astype(np.int64)
    if "pose_names" in arrays:
        poses = tuple(str(p) for p in _array(arrays, "pose_names", "U", 1, path))
        if len(poses) != times.shape[0]:
            raise MotionToolError(f"'{path}': {len(poses)} pose_names for {times.shape[0]} poses")
    else:
        poses = tuple(pose_name(int(t)) for t in times)
    try:
        joints = tuple(check_name(str(n), "joint") for n in arrays["names"])
        for pose in poses:
            check_name(pose, "pose name")
    except MotionToolError as exc:
        raise MotionToolError(f"'{path}': {exc}") from exc
    motion = Motion(
        joints, poses, times, arrays["positions"].astype(np.float64), arrays["commanded"]
    )
    return Imported(motion, path)
