"""``motions.toml``: expectations (and a start state) for motion files, kept beside them.

Webots reads a ``.motion`` file as a whole: nothing can be added to it. A sidecar in the
motion's folder, or in a folder above it, says what each motion must do::

    ["Turn*"]                     # a glob of motion names (file stems), case-sensitive
    expect = ["upright"]

    [TurnLeft60]                  # a motion name
    expect = ["yaw=60±10"]        # motiontool.sim.expect syntax

    [StandUpFromFront]
    expect = ["upright"]
    start = "lying-front"         # standing, lying-front, lying-back

    ["nao/*"]                     # a key with '/' matches the path below the sidecar's folder
    expect = ["feet-planted"]     #   (without .motion; '*' matches '/' too: all below nao/)

    ["wrestling/*"]
    world = "../worlds/wrestling.wbt"   # the Webots world it plays in (from this folder)
    robot-node = "participant"          # the world's robot node that plays it (name or DEF)

    [SideStepLeft_Loop]
    after = "SideStepLeft_Start"  # the motion played before it (a chain): its name, beside it

Every section that matches a motion applies, in file order (expectations add up); for
``start``, ``world`` (with its ``robot-node``) and ``after``, a section that names the motion
beats a glob, and of two globs the first wins. The
sidecar of a motion is the nearest ``motions.toml`` from the motion's folder up to the search
boundary (:func:`search_boundary`); sidecars do not merge. Read with the standard ``tomllib``.
"""

from __future__ import annotations

import difflib
import os
import tomllib
from dataclasses import dataclass
from fnmatch import fnmatchcase
from pathlib import Path, PurePath
from typing import Any

from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.motionfmt.structured_text import load_toml
from motiontool.sim.expect import ExpectationError, parse_expectation
from motiontool.sim.start import StartState

__all__ = [
    "SIDECAR_NAME",
    "Section",
    "Sidecar",
    "SidecarEntry",
    "SidecarError",
    "after_path",
    "expectations_for",
    "find_sidecar",
    "load_sidecar",
    "lookup",
    "search_boundary",
]

SIDECAR_NAME = "motions.toml"
"""The file name of a sidecar."""

_KEYS = ("expect", "start", "world", "robot-node", "after")


class SidecarError(MotionToolError):
    """A sidecar that cannot be used: ``motions.toml:LINE: what is wrong``."""


@dataclass(frozen=True)
class Section:
    """One ``[name]`` table: its key (a name or a glob), line, expectations and start, and the
    world (a path from the current directory) and its robot node."""

    key: str
    line: int
    expect: tuple[str, ...]
    start: str | None
    world: Path | None = None
    robot_node: str | None = None
    after: str | None = None

    @property
    def is_glob(self) -> bool:
        return any(c in self.key for c in "*?[")

    def matches(self, motion: Path, folder: Path) -> bool:
        if "/" in self.key:
            try:
                rel = Path(os.path.abspath(motion)).relative_to(os.path.abspath(folder))
            except ValueError:
                return False
            return fnmatchcase(PurePath(rel).with_suffix("").as_posix(), self.key)
        return fnmatchcase(motion.stem, self.key)


@dataclass(frozen=True)
class SidecarEntry:
    """What a sidecar says about one motion: where from, the sections that matched, the
    expectations (texts, in file order), the start state, the world with its robot node and
    the motion played before it (``after``, as written: a motion name) (None: not set)."""

    path: Path
    sections: tuple[str, ...]
    expect: tuple[str, ...]
    start: str | None
    world: Path | None = None
    robot_node: str | None = None
    after: str | None = None


@dataclass(frozen=True)
class Sidecar:
    """A parsed, checked ``motions.toml``."""

    path: Path
    sections: tuple[Section, ...]

    def lookup(self, motion: str | Path) -> SidecarEntry | None:
        """The entry for ``motion`` (None if no section matches it)."""
        motion = Path(motion)
        matched = [s for s in self.sections if s.matches(motion, self.path.parent)]
        if not matched:
            return None
        expect = tuple(e for s in matched for e in s.expect)
        starts = [s for s in matched if s.start is not None]
        starts.sort(key=lambda s: s.is_glob)  # stable: exact names first, then file order
        worlds = sorted((s for s in matched if s.world is not None), key=lambda s: s.is_glob)
        afters = sorted((s for s in matched if s.after is not None), key=lambda s: s.is_glob)
        return SidecarEntry(
            self.path,
            tuple(s.key for s in matched),
            expect,
            starts[0].start if starts else None,
            worlds[0].world if worlds else None,
            worlds[0].robot_node if worlds else None,
            afters[0].after if afters else None,
        )


def _header_lines(lines: list[str]) -> dict[str, int]:
    """Table name -> its 1-based line (each ``[...]`` line parsed by tomllib alone)."""
    out: dict[str, int] = {}
    for number, line in enumerate(lines, 1):
        if not line.lstrip().startswith("[") or line.lstrip().startswith("[["):
            continue
        try:
            parsed = tomllib.loads(line)
        except (tomllib.TOMLDecodeError, RecursionError):
            continue
        for key in parsed:
            out.setdefault(key, number)
    return out


def _line_of(lines: list[str], start: int, needle: str) -> int:
    """The first line from ``start`` (1-based) that holds ``needle``, up to the next table."""
    for number in range(start, len(lines) + 1):
        text = lines[number - 1]
        if number > start and text.lstrip().startswith("["):
            break
        if needle in text:
            return number
    return start


def load_sidecar(path: str | Path) -> Sidecar:
    """Read and check a sidecar: every expectation is parsed, every key known.

    Raises:
        SidecarError: ``PATH:LINE: ...`` (one line) for bad TOML, a key other than ``expect``
            and ``start``, an expectation that does not parse, a start that does not exist.
        MotionToolError: the file cannot be read (``cannot read 'PATH': REASON``).
    """
    path = Path(path)
    text, doc = _read_toml(path)
    lines = text.splitlines()
    headers = _header_lines(lines)
    sections = []
    for key, table in doc.items():
        line = headers.get(key) or _line_of(lines, 1, key)
        if not isinstance(table, dict):
            raise SidecarError(
                f"{path}:{line}: '{key}' is not a [section]; put expectations under a motion "
                f'name or glob, e.g. ["*"] then expect = [...]'
            )
        sections.append(_section(path, lines, key, line, table))
    return Sidecar(path, tuple(sections))


def _read_toml(path: Path) -> tuple[str, dict[str, Any]]:
    """The text of the sidecar at ``path`` and its TOML document; an error says where."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise MotionToolError(f"cannot read '{path}': {exc.strerror or exc}") from exc
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise SidecarError(f"{path}:{line}: not UTF-8 (TOML files are UTF-8)") from None
    try:
        return text, load_toml(text, str(path), "a motions.toml")
    except MotionSyntaxError as exc:
        raise SidecarError(f"{path}:{exc.line}:{exc.column}: {exc.message}") from None


def _section(path: Path, lines: list[str], key: str, line: int, table: dict[str, Any]) -> Section:
    """The ``[key]`` table at ``line``, checked: known keys, expectations that parse, a start
    state that exists."""
    for name in table:
        if name not in _KEYS:
            close = difflib.get_close_matches(name, _KEYS, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            where = _line_of(lines, line, name)
            raise SidecarError(
                f"{path}:{where}: unknown key '{name}' in [{key}]{hint} (keys: {', '.join(_KEYS)})"
            )
    expect = table.get("expect", [])
    if isinstance(expect, str):
        expect = [expect]
    if not isinstance(expect, list) or not all(isinstance(e, str) for e in expect):
        where = _line_of(lines, line, "expect")
        raise SidecarError(
            f"{path}:{where}: expect in [{key}] must be a list of strings, "
            f'e.g. expect = ["dx>0", "upright"]'
        )
    for e in expect:
        try:
            parse_expectation(e)
        except ExpectationError as exc:
            raise SidecarError(f"{path}:{_line_of(lines, line, e)}: {exc}") from None
    start = table.get("start")
    if start is not None and start not in set(StartState):
        where = _line_of(lines, line, "start")
        raise SidecarError(
            f"{path}:{where}: start {start!r} in [{key}]: choose {', '.join(StartState)}"
        )
    world, robot_node = _world(path, lines, key, line, table)
    after = table.get("after")
    if after is not None and (not isinstance(after, str) or not after):
        where = _line_of(lines, line, "after")
        raise SidecarError(
            f"{path}:{where}: after in [{key}] must be a string: the name of the motion played "
            'before, e.g. after = "Walk_Start"'
        )
    return Section(key, line, tuple(expect), start, world, robot_node, after)


def _world(
    path: Path, lines: list[str], key: str, line: int, table: dict[str, Any]
) -> tuple[Path | None, str | None]:
    """The ``world`` of the ``[key]`` table (a file, from the sidecar's folder) and its
    ``robot-node``, checked: strings, a world file that exists, no robot node without one."""
    world, node = table.get("world"), table.get("robot-node")
    for name, value in (("world", world), ("robot-node", node)):
        if value is not None and not isinstance(value, str):
            where = _line_of(lines, line, name)
            raise SidecarError(f"{path}:{where}: {name} in [{key}] must be a string")
    if world is None:
        if node is not None:
            where = _line_of(lines, line, "robot-node")
            raise SidecarError(f"{path}:{where}: robot-node in [{key}] without a world")
        return None, None
    found = path.parent / world
    if not found.is_file():
        where = _line_of(lines, line, "world")
        raise SidecarError(f"{path}:{where}: world {world!r} in [{key}]: no such file ({found})")
    return found, node


def after_path(entry: SidecarEntry, motion: str | Path) -> Path:
    """The motion file ``entry.after`` names for ``motion``: a name is the file of that stem
    beside ``motion`` (``Walk_Start``: ``Walk_Start.motion``); a path (with ``/`` or the
    ``.motion`` suffix) is from the sidecar's folder.

    Raises:
        SidecarError: ``motions.toml:LINE: after 'X' in [key]: no such motion (PATH)``.
    """
    assert entry.after is not None
    after = entry.after
    if "/" in after or after.endswith(".motion"):
        found = entry.path.parent / after
    else:
        found = Path(motion).parent / f"{after}.motion"
    if found.is_file():
        return found
    sidecar = load_sidecar(entry.path)
    section = next(s for s in sidecar.sections if s.key in entry.sections and s.after == after)
    lines = _read_toml(entry.path)[0].splitlines()
    where = _line_of(lines, section.line, "after")
    raise SidecarError(
        f"{entry.path}:{where}: after {after!r} in [{section.key}]: no such motion ({found})"
    )


def search_boundary(motion: str | Path, roots: tuple[Path, ...] | list[Path] = ()) -> Path:
    """The highest folder searched for the sidecar of ``motion``: the current directory when
    the motion lies below it, else the first of ``roots`` (e.g. a batch's directory
    arguments) that holds it, else the motion's own folder."""
    here = Path(os.path.abspath(motion)).parent
    for top in (Path.cwd(), *roots):
        top = Path(os.path.abspath(top))
        if here == top or top in here.parents:
            return top
    return here


def find_sidecar(motion: str | Path, boundary: str | Path | None = None) -> Path | None:
    """The nearest ``motions.toml`` from ``motion``'s folder up to ``boundary`` (included;
    default: :func:`search_boundary`), or None."""
    here = Path(os.path.abspath(motion)).parent
    top = Path(os.path.abspath(boundary)) if boundary is not None else search_boundary(motion)
    folder = here
    while True:
        candidate = folder / SIDECAR_NAME
        if candidate.is_file():
            return _shown(candidate)
        if folder == top or folder.parent == folder or top not in folder.parents:
            return None
        folder = folder.parent


def lookup(
    motion: str | Path,
    roots: tuple[Path, ...] | list[Path] = (),
    cache: dict[Path, Sidecar] | None = None,
) -> SidecarEntry | None:
    """What the nearest sidecar of ``motion`` says about it (None: no sidecar, or no section
    for it). ``roots`` as for :func:`search_boundary`; ``cache`` keeps parsed sidecars between
    calls (keyed by path)."""
    found = find_sidecar(motion, search_boundary(motion, roots))
    if found is None:
        return None
    if cache is None:
        return load_sidecar(found).lookup(motion)
    if found not in cache:
        cache[found] = load_sidecar(found)
    return cache[found].lookup(motion)


def expectations_for(
    motion: str | Path,
    extra: tuple[str, ...] | list[str] = (),
    *,
    sidecar: bool = True,
    roots: tuple[Path, ...] | list[Path] = (),
    cache: dict[Path, Sidecar] | None = None,
) -> tuple[tuple[str, ...], str | None]:
    """The expectations of ``motion`` (its sidecar's, then ``extra``, e.g. ``--expect``), and
    the sidecar's start state (None: not set). ``sidecar=False`` reads no sidecar."""
    entry = lookup(motion, roots, cache) if sidecar else None
    if entry is None:
        return tuple(extra), None
    return entry.expect + tuple(extra), entry.start


def _shown(path: Path) -> Path:
    """``path`` relative to the current directory where it lies below it (error messages)."""
    try:
        return path.relative_to(Path.cwd())
    except ValueError:
        return path
