"""The :class:`~motiontool.kinematics._pinocchio.KinematicTables` of a robot, kept on disk.

Building a robot's tables imports Pinocchio (about 0.15 s) and builds its model; the collision
check (:mod:`motiontool.kinematics.collision`) needs Pinocchio after that only for the few
(configuration, pair)s that its numpy bounds cannot clear. A motion that brings no two
bodies near each other, as most do, is then checked without importing Pinocchio at all, once
the tables are on disk: ``$XDG_CACHE_HOME/motiontool/kinematics`` (``~/.cache/...``).

A stored table is used only for the same robot model (its sha256, overrides included), the
same motors, the same way of building it (format, free-flying root) and the same code: the key
hashes the source of the modules that compute the tables and the installed Pinocchio's files.
Anything else, or a file that cannot be read, builds the tables again (and stores them); a
cache that cannot be written is not an error.
"""

from __future__ import annotations

import functools
import hashlib
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.disk_cache import cache_root, libraries_stamp, write_replacing
from motiontool.kinematics._pinocchio import KinematicTables, kinematic_tables
from motiontool.kinematics.robots import RobotSpec

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["cache_dir", "stored_tables", "tables_key"]

#: The modules whose code decides what the tables hold: a change to one is a new key.
_SOURCES = ("_pinocchio/tables.py", "_pinocchio/shapes.py", "_pinocchio/model.py")
#: The fields of :class:`KinematicTables` that are tuples of names, not arrays.
_NAMES = ("geom_body", "geom_limb")
#: A stored table: its fields as ``.npy`` arrays one after another, in field order
#: (``np.save`` to one file, ``np.load`` reads them back in turn). No zip archive (``.npz``)
#: to open: reading one imports no :mod:`zipfile` and parses no archive directory.
_SUFFIX = ".npy"


def cache_dir() -> Path:
    """``$XDG_CACHE_HOME/motiontool/kinematics`` (``~/.cache/motiontool/kinematics``)."""
    return cache_root() / "kinematics"


@functools.cache
def _code_stamp() -> str:
    """Hash of the table code and of the installed Pinocchio (its path, size and mtime)."""
    h = hashlib.sha256()
    here = Path(__file__).parent
    for name in _SOURCES:
        h.update((here / name).read_bytes())
    h.update(libraries_stamp("pinocchio").encode("utf-8", "surrogateescape"))
    return h.hexdigest()


def tables_key(spec: RobotSpec) -> str:
    """What a stored table is found by (hex): the model, the motors, how the model is built
    and the code that builds the tables."""
    return spec.model_key(_code_stamp())


_IN_PROCESS: dict[tuple[Path, str], KinematicTables] = {}
"""The tables read or built in this process, by cache folder and key."""


def stored_tables(spec: RobotSpec) -> KinematicTables:
    """``spec``'s tables: from the disk cache if they are there (no Pinocchio import), else
    built by :func:`~motiontool.kinematics._pinocchio.kinematic_tables` and stored; once per
    process and robot."""
    folder, key = cache_dir(), tables_key(spec)
    tables = _IN_PROCESS.get((folder, key))
    if tables is None:
        path = folder / f"{key}{_SUFFIX}"
        tables = _load(path)
        if tables is None:
            tables = kinematic_tables(spec)
            _save(path, tables)
        _IN_PROCESS[(folder, key)] = tables
    return tables


def _load(path: Path) -> KinematicTables | None:
    """The tables stored at ``path``, or None (missing, unreadable, or of another layout)."""
    import numpy as np

    try:
        with path.open("rb") as stored:
            fields: dict[str, object] = {}
            for name in KinematicTables._fields:
                value: npt.NDArray[np.void] = np.load(stored, allow_pickle=False)
                if name in _NAMES:
                    fields[name] = tuple(str(s) for s in value.tolist())
                elif name == "exact":
                    fields[name] = bool(value)
                else:
                    value.flags.writeable = False
                    fields[name] = value
    except (OSError, ValueError, EOFError):
        return None
    return KinematicTables(**fields)  # type: ignore[arg-type]  # the layout _save wrote


def _save(path: Path, tables: KinematicTables) -> None:
    """Store ``tables`` at ``path`` (:func:`motiontool.disk_cache.write_replacing`: no
    temporary file left by a signal); a failure is ignored: the next run builds them again."""
    import io

    import numpy as np

    stream = io.BytesIO()
    for value in tables:
        np.save(stream, np.array(value), allow_pickle=False)
    write_replacing(path, stream.getvalue())
