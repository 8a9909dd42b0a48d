"""Project configuration: ``[tool.motiontool]`` in ``pyproject.toml`` or a ``motiontool.toml``.

The file that applies to a motion file is the closest one found walking up from the file's
folder (as ruff finds its configuration): in each folder, ``motiontool.toml`` (its keys at the
top level), then ``pyproject.toml`` if it has a ``[tool.motiontool]`` table. ``--config PATH``
names one file for every input; ``--isolated`` reads none. Options on the command line
override the file. Globs (``[tool.motiontool.robots]``, ``per-file-ignores``, ``exclude``) are
relative to the folder of the file that holds them.

Keys (``cli/schemas/config.schema.json`` is their JSON Schema, shipped in the package):

- ``robot``: the robot files are checked and played against (``auto``, ``nao``, ``ur5e``, ...);
- ``[tool.motiontool.robots]``: ``"GLOB" = "ROBOT"``, the robot for the files a glob matches
  (the first match wins; ``robot`` for the others);
- ``select``, ``extend-select``, ``ignore``, ``extend-ignore``: codes (or prefixes: ``MT2``)
  reported / left out, as ruff selects its rules (:class:`Selection`: the most specific
  selector decides; ``--select`` on the command line replaces the file's selection);
- ``per-file-ignores``: ``"GLOB" = ["MT206"]``;
- ``strict``: warnings fail the run too;
- ``checks``: the robot checks (``["limits", "velocity"]``);
- ``timestep``: the controller time step in ms;
- ``exclude``, ``extend-exclude``: files and folders left out when a folder is searched;
- ``force-exclude``: ``exclude`` applies to files named on the command line too (what the
  pre-commit hook turns on: pre-commit names every staged file);
- ``respect-gitignore``: folder searches leave out what ``.gitignore`` files ignore, and
  hidden folders (default true);
- ``max-findings``: findings shown at most (the summary still counts every one);
- ``group``: consecutive per-pose findings of one code and joint as one finding (default true);
- ``world``, ``robot-node``: the Webots world ``play`` and ``batch`` play in (a path from the
  file's folder) and its robot node, where neither the command line nor ``motions.toml`` names one.

A key that does not exist or a value of the wrong type is one error naming the file, the line
and the key, with a did-you-mean.
"""

from __future__ import annotations

import difflib
import fnmatch
import re
from collections.abc import Iterable
from pathlib import Path, PurePosixPath
from typing import Annotated, Any, NamedTuple

import typer

from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.kinematics.checks.registry import CHECKS

__all__ = [
    "CONFIG_NAMES",
    "KEYS",
    "ConfigError",
    "ConfigOption",
    "IsolatedOption",
    "Resolver",
    "Selection",
    "Settings",
    "check_selectors",
    "load_settings",
]

CONFIG_NAMES = ("motiontool.toml", "pyproject.toml")
"""The files looked for in each folder, in this order."""


ConfigOption = Annotated[
    Path | None,
    typer.Option(
        "--config",
        help="Use this configuration file (a motiontool.toml, or a pyproject.toml with "
        "[tool.motiontool]) for every file, instead of the closest one.",
        show_default=False,
    ),
]
IsolatedOption = Annotated[
    bool, typer.Option("--isolated", help="Read no configuration file: defaults and options only.")
]


class ConfigError(MotionToolError):
    """A configuration file that cannot be used: ``FILE:LINE: KEY: what is wrong``. Also the
    file, its 1-based line and column (where known: the editor shows the error there)."""

    def __init__(self, message: str, path: Path | None = None, line: int = 1, column: int = 1):
        super().__init__(message)
        self.path, self.line, self.column = path, line, column


class Selection(NamedTuple):
    """One source's choice of codes (a configuration file, or the command line), as ruff
    selects rules: codes or prefixes (``MT2``) to report (``select``: these and no others;
    ``extend_select``: these too) and to leave out (``ignore``).

    Within a source the most specific selector that matches a code decides (``select = MT2``
    with ``ignore = MT203`` leaves MT203 out; ``select = MT203`` with ``ignore = MT2`` keeps
    it), an ignore winning a tie; a later source's ``select`` replaces what the earlier ones
    chose, its ``extend_select`` and ``ignore`` change only the codes they match.
    """

    select: tuple[str, ...] | None = None
    extend_select: tuple[str, ...] = ()
    ignore: tuple[str, ...] = ()

    def decide(self, code: str, earlier: bool) -> bool:
        """Whether ``code`` is reported after this source, given ``earlier``: what the
        sources before it decided."""
        best: tuple[int, bool] | None = None
        for selector in (*(self.select or ()), *self.extend_select):
            if code.startswith(selector) and (best is None or len(selector) > best[0]):
                best = (len(selector), True)
        for selector in self.ignore:
            if code.startswith(selector) and (best is None or len(selector) >= best[0]):
                best = (len(selector), False)
        if best is not None:
            return best[1]
        return False if self.select is not None else earlier


def check_selectors(codes: Iterable[str], option: str) -> tuple[str, ...]:
    """``codes`` given to ``option`` (repeated or comma-separated), upper case: codes or
    prefixes of codes (``MT2``).

    Raises:
        MotionToolError: ``OPTION: unknown code 'X'; did you mean ...``.
    """
    found = tuple(c.strip().upper() for item in codes for c in item.split(",") if c.strip())
    bad = _unknown_value("ignore", list(found)) if found else None
    if bad is not None:
        raise MotionToolError(f"{option}: {bad}")
    return found


class Settings(NamedTuple):
    """The settings a configuration file gives (defaults where it says nothing).

    Attributes:
        source: the file they come from (None: no file, the defaults).
        root: the folder globs are relative to (the file's folder; the working directory for
            the defaults: ``.``).
    """

    source: Path | None = None
    root: Path = Path()
    robot: str = "auto"
    robots: tuple[tuple[str, str], ...] = ()
    select: tuple[str, ...] | None = None
    extend_select: tuple[str, ...] = ()
    ignore: tuple[str, ...] = ()
    extend_ignore: tuple[str, ...] = ()
    per_file_ignores: tuple[tuple[str, tuple[str, ...]], ...] = ()
    strict: bool = False
    checks: tuple[str, ...] | None = None
    timestep: int | None = None
    exclude: tuple[str, ...] = ()
    extend_exclude: tuple[str, ...] = ()
    force_exclude: bool = False
    respect_gitignore: bool = True
    max_findings: int | None = None
    group: bool = True
    world: Path | None = None
    robot_node: str | None = None

    def robot_for(self, path: Path) -> str:
        """The robot for ``path``: the first ``robots`` glob that matches it, else ``robot``."""
        for pattern, robot in self.robots:
            if self.matches(pattern, path):
                return robot
        return self.robot

    @property
    def selection(self) -> Selection:
        """The codes this file selects and ignores (``per-file-ignores`` aside)."""
        return Selection(self.select, self.extend_select, (*self.ignore, *self.extend_ignore))

    def reports(self, code: str, path: Path, cli: Selection | None = None) -> bool:
        """Whether a finding ``code`` in ``path`` is reported: this file's
        :attr:`selection`, then the command line's (``cli``), then ``per-file-ignores`` (a
        prefix such as ``MT2`` stands for every code that starts with it)."""
        return code not in self.unreported(path, (code,), cli)

    def unreported(
        self, path: Path, codes: Iterable[str], cli: Selection | None = None
    ) -> frozenset[str]:
        """Of ``codes``, those :meth:`reports` leaves out in ``path`` (its
        ``per-file-ignores`` matched once for them all)."""
        matched = [codes for pattern, codes in self.per_file_ignores if self.matches(pattern, path)]
        ignored = tuple(c for prefixes in matched for c in prefixes)
        left_out = set()
        for code in codes:
            enabled = self.selection.decide(code, True)
            if cli is not None:
                enabled = cli.decide(code, enabled)
            if not enabled or code.startswith(ignored):
                left_out.add(code)
        return frozenset(left_out)

    def excluded(self, path: Path) -> bool:
        """Whether ``path`` (found by searching a folder, or named with ``force-exclude``)
        is left out: a glob matches it or a folder it is in."""
        globs = (*self.exclude, *self.extend_exclude)
        if not globs:
            return False
        return any(self.matches(g, q) for q in (path, *self._folders_of(path)) for g in globs)

    def _folders_of(self, path: Path) -> list[Path]:
        """The folders ``path`` is in below :attr:`root` (none outside it)."""
        try:
            rel = _resolved(path).relative_to(self.root.resolve())
        except ValueError:
            return []
        return [self.root / p for p in rel.parents if p != Path(".")]

    def matches(self, pattern: str, path: Path) -> bool:
        """``pattern`` against ``path`` relative to :attr:`root`: a pattern with a ``/``
        matches the relative path (``*`` and ``**`` cross folders), one without matches any
        folder name on the way or the file name."""
        try:
            rel = PurePosixPath(_resolved(path).relative_to(self.root.resolve()).as_posix())
        except ValueError:
            rel = PurePosixPath(path.as_posix())
        if "/" in pattern.rstrip("/"):
            return fnmatch.fnmatchcase(rel.as_posix(), pattern.rstrip("/"))
        return any(fnmatch.fnmatchcase(part, pattern.rstrip("/")) for part in rel.parts)

    def as_dict(self) -> dict[str, Any]:
        """The settings as the configuration file spells them (``--show-settings``)."""
        out: dict[str, Any] = {"source": None if self.source is None else str(self.source)}
        out["root"] = str(self.root.resolve())
        for name in self._fields:
            if name in ("source", "root"):
                continue
            value = getattr(self, name)
            if name in ("robots", "per_file_ignores"):
                value = {k: list(v) if isinstance(v, tuple) else v for k, v in value}
            elif isinstance(value, tuple):
                value = list(value)
            elif isinstance(value, Path):
                value = str(value)
            out[name.replace("_", "-")] = value
        return out


def _strings(value: Any) -> bool:
    return isinstance(value, list) and all(isinstance(v, str) for v in value)


def _table_of(kind: str) -> Any:
    def check(value: Any) -> bool:
        if not isinstance(value, dict):
            return False
        if kind == "str":
            return all(isinstance(v, str) for v in value.values())
        return all(_strings(v) for v in value.values())

    return check


_QUOTED_CHECKS = ", ".join(f'"{name}"' for name in CHECKS)

# key -> (check, what the value must be)
KEYS: dict[str, tuple[Any, str]] = {
    "robot": (lambda v: isinstance(v, str), "a robot name (string)"),
    "robots": (_table_of("str"), 'a table of "GLOB" = "ROBOT"'),
    "select": (_strings, "a list of codes"),
    "extend-select": (_strings, "a list of codes"),
    "ignore": (_strings, "a list of codes"),
    "extend-ignore": (_strings, "a list of codes"),
    "per-file-ignores": (_table_of("list"), 'a table of "GLOB" = ["CODE", ...]'),
    "strict": (lambda v: isinstance(v, bool), "true or false"),
    "checks": (_strings, f"a list of checks ({_QUOTED_CHECKS})"),
    "timestep": (
        lambda v: isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= 2**31 - 1,
        "a whole number of ms >= 1",
    ),
    "exclude": (_strings, "a list of globs"),
    "extend-exclude": (_strings, "a list of globs"),
    "force-exclude": (lambda v: isinstance(v, bool), "true or false"),
    "respect-gitignore": (lambda v: isinstance(v, bool), "true or false"),
    "max-findings": (
        lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 1,
        "a whole number >= 1",
    ),
    "group": (lambda v: isinstance(v, bool), "true or false"),
    "world": (lambda v: isinstance(v, str) and v != "", "a Webots world file (a path, string)"),
    "robot-node": (lambda v: isinstance(v, str) and v != "", "a robot node's name or DEF"),
}
"""Every configuration key, with the check of its value and what that value must be."""


def _line_of(text: str, key: str, table: str | None) -> int:
    """The 1-based line where ``key`` is set in ``[table]`` (the top level when None): its
    ``key =`` line, else its own ``[table.key]`` header, else the table's header, else 1."""
    lines = text.splitlines()
    header = re.compile(r"^\s*\[\s*([^\]]+?)\s*\]\s*(#.*)?$")
    current: str | None = None
    assignment = re.compile(rf"^\s*[\"']?{re.escape(key)}[\"']?\s*=")
    table_line = None
    for number, line in enumerate(lines, 1):
        found = header.match(line)
        if found:
            current = found.group(1).replace(" ", "")
            if current == (f"{table}.{key}" if table else key):
                return number
            if current == table:
                table_line = number
            continue
        if current == table and assignment.match(line):
            return number
    return table_line or 1


def _may_name_motiontool(text: str) -> bool:
    """Whether TOML ``text`` can hold a ``[tool.motiontool]`` table: every way of writing the
    key spells ``motiontool``, but a quoted key with ``\\u`` escapes. A project's
    ``pyproject.toml`` without it (the hook run in a repository that configures nothing) is
    left unparsed: ``tomllib``'s import and the parse, about 3 ms of a 0.08 s run."""
    return "motiontool" in text or "\\u" in text or "\\U" in text


def _read(path: Path) -> tuple[dict[str, Any] | None, str, str | None]:
    """(the motiontool table or None, the file's text, the table's dotted name). A file read
    before with the same text is not parsed again (:mod:`motiontool.cli.config_cache`)."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) else "not UTF-8"
        raise ConfigError(f"cannot read '{path}': {reason}", path) from exc
    pyproject = path.name == "pyproject.toml"
    name = "tool.motiontool" if pyproject else None
    if pyproject and not _may_name_motiontool(text):
        return None, text, name  # another tool's file: not parsed, not judged
    from motiontool.cli import config_cache  # where a file is found

    kept = config_cache.lookup(path, text)
    if kept is not None:
        return kept.table, text, name
    from motiontool.motionfmt.structured_text import load_toml

    try:
        doc = load_toml(text, str(path), "a configuration")
    except MotionSyntaxError as exc:
        where = f"line {exc.line}, column {exc.column}"
        raise ConfigError(
            f"{path}: not valid TOML: {exc.message} (at {where})", path, exc.line, exc.column
        ) from exc
    tool = doc.get("tool") if pyproject else {"motiontool": doc}
    table = tool.get("motiontool") if isinstance(tool, dict) else None
    table = table if isinstance(table, dict) else None
    config_cache.store(path, text, table)
    return table, text, name


def load_settings(path: Path) -> Settings | None:
    """The settings of configuration file ``path``, or None for a ``pyproject.toml`` without
    a ``[tool.motiontool]`` table.

    Raises:
        ConfigError: ``FILE:LINE: KEY: ...``: an unknown key (with a did-you-mean), a value of
            the wrong type, a file that is not TOML or cannot be read.
    """
    table, text, name = _read(path)
    if table is None:
        return None
    values: dict[str, Any] = {}
    for key, value in table.items():
        if key not in KEYS:
            close = difflib.get_close_matches(key, KEYS, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else f"; keys: {', '.join(KEYS)}"
            line = _line_of(text, key, name)
            raise ConfigError(f"{path}:{line}: unknown key '{key}'{hint}", path, line)
        check, what = KEYS[key]
        if not check(value):
            line = _line_of(text, key, name)
            raise ConfigError(f"{path}:{line}: '{key}' must be {what}, got {value!r}", path, line)
        bad = _unknown_value(key, value)
        if bad is not None:
            line = _line_of(text, key, name)
            raise ConfigError(f"{path}:{line}: '{key}': {bad}", path, line)
        values[key.replace("-", "_")] = value
    if "world" in values or "robot_node" in values:
        values["world"] = _world_file(path, text, name, values)
    return _settings(path, values)


def _world_file(path: Path, text: str, table: str | None, values: dict[str, Any]) -> Path:
    """The file ``world`` names (from the folder of ``path``, the configuration file).

    Raises:
        ConfigError: ``robot-node`` without ``world``, or a world that is no file."""
    if "world" not in values:
        line = _line_of(text, "robot-node", table)
        what = "'robot-node' names a node of 'world': set world too"
        raise ConfigError(f"{path}:{line}: {what}", path, line)
    found: Path = path.resolve().parent / values["world"]
    if not found.is_file():
        line = _line_of(text, "world", table)
        what = f"'world': no such file '{values['world']}' ({found})"
        raise ConfigError(f"{path}:{line}: {what}", path, line)
    return found


def _did_you_mean(word: str, choices: Iterable[str]) -> str:
    close = difflib.get_close_matches(word, list(choices), n=1)
    return f"; did you mean '{close[0]}'?" if close else ""


def _unknown_value(key: str, value: Any) -> str | None:
    """What is wrong with a value of the right type (an unknown check or code), or None."""
    from motiontool.kinematics.checks import CHECKS
    from motiontool.motionfmt.diagnostics import CODES

    if key == "checks":
        for name in value:
            if name not in (*CHECKS, "all"):
                hint = _did_you_mean(name, CHECKS) or f"; checks: {', '.join(CHECKS)} or all"
                return f"unknown check '{name}'{hint}"
    codes: list[str] = []
    if key in ("select", "extend-select", "ignore", "extend-ignore"):
        codes = list(value)
    elif key == "per-file-ignores":
        codes = [c for listed in value.values() for c in listed]
    for code in codes:
        upper = code.strip().upper()
        if not any(known.startswith(upper) for known in CODES) or not upper.startswith("MT"):
            hint = _did_you_mean(upper, CODES) or "; 'motiontool codes' lists them"
            return f"unknown code '{code}'{hint}"
    return None


def _codes(values: Iterable[str]) -> tuple[str, ...]:
    return tuple(c.strip().upper() for c in values)


def _settings(path: Path, values: dict[str, Any]) -> Settings:
    select = values.get("select")
    checks = values.get("checks")
    return Settings(
        source=path.resolve(),
        root=path.resolve().parent,
        robot=values.get("robot", "auto"),
        robots=tuple(values.get("robots", {}).items()),
        select=None if select is None else _codes(select),
        extend_select=_codes(values.get("extend_select", ())),
        ignore=_codes(values.get("ignore", ())),
        extend_ignore=_codes(values.get("extend_ignore", ())),
        per_file_ignores=tuple(
            (glob, _codes(codes)) for glob, codes in values.get("per_file_ignores", {}).items()
        ),
        strict=values.get("strict", False),
        checks=None if checks is None else tuple(checks),
        timestep=values.get("timestep"),
        exclude=tuple(values.get("exclude", ())),
        extend_exclude=tuple(values.get("extend_exclude", ())),
        force_exclude=values.get("force_exclude", False),
        respect_gitignore=values.get("respect_gitignore", True),
        max_findings=values.get("max_findings"),
        group=values.get("group", True),
        world=values.get("world"),
        robot_node=values.get("robot_node"),
    )


def _resolved(path: Path) -> Path:
    """``path`` made absolute, its links followed; a link that comes back to itself (which
    :meth:`Path.resolve` refuses) stays a name in its folder, resolved."""
    try:
        return path.resolve()
    except (RuntimeError, OSError):  # RuntimeError: a symbolic link loop (Python < 3.13)
        return path.parent.resolve() / path.name


class Resolver:
    """The settings for each motion file: the closest configuration file up from it (each
    file read once), one named file (``config``), or none (``isolated``)."""

    def __init__(self, *, config: Path | None = None, isolated: bool = False) -> None:
        if isolated and config is not None:
            raise MotionToolError("--isolated reads no configuration file: leave out --config")
        self.isolated = isolated
        self._fixed: Settings | None = None
        self._by_folder: dict[Path, Settings] = {}
        if config is not None and not isolated:
            if not config.is_file():
                raise ConfigError(f"cannot read '{config}': No such file")
            self._fixed = load_settings(config) or Settings(
                source=config.resolve(), root=config.resolve().parent
            )

    def for_file(self, path: Path) -> Settings:
        """The settings that apply to ``path`` (``-``: those of the working directory)."""
        if self.isolated:
            return Settings()
        if self._fixed is not None:
            return self._fixed
        if str(path) == "-":
            return self._for_folder(Path.cwd())
        return self._for_folder(_resolved(path).parent)

    def _for_folder(self, folder: Path) -> Settings:
        if folder in self._by_folder:
            return self._by_folder[folder]
        found: Settings | None = None
        for name in CONFIG_NAMES:
            candidate = folder / name
            try:
                exists = candidate.is_file()
            except OSError:  # a folder that may not be searched holds no configuration for us
                exists = False
            if exists:
                found = load_settings(candidate)
                if found is not None:
                    break
        if found is None:
            found = Settings() if folder.parent == folder else self._for_folder(folder.parent)
        self._by_folder[folder] = found
        return found

    def sources(self, paths: Iterable[Path]) -> list[Path]:
        """The configuration files used for ``paths``, each once, in first-use order."""
        seen: dict[Path, None] = {}
        for p in paths:
            s = self.for_file(p)
            if s.source is not None:
                seen.setdefault(s.source, None)
        return list(seen)
