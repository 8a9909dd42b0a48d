"""``motiontool server``: the Language Server on stdio (:mod:`motiontool.cli.lsp`)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from motiontool.cli.config import ConfigOption, IsolatedOption, Resolver
from motiontool.cli.lint_run import Overrides, lint_document
from motiontool.cli.options import NoCacheOption
from motiontool.cli.validate import robot_checks
from motiontool.extras import require
from motiontool.kinematics.checks import DEFAULT_PENETRATION_TOLERANCE_MM, RobotChecks
from motiontool.kinematics.checks.findings_cache import MAX_BYTES, FindingsCache
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.reread import Rereader
from motiontool.motionfmt.validate import FileReport

__all__ = ["server_command"]


def server_command(
    config: ConfigOption = None, isolated: IsolatedOption = False, no_cache: NoCacheOption = False
) -> None:
    """Run the Language Server on stdin/stdout, for editors: the findings of ``validate`` as you
    type (with the project's configuration, the closest to each file), hover on a cell (joint,
    time, value, limits) and the fixes of ``validate --fix`` as code actions.

    Editors start it themselves (docs/editor.md: Neovim, VS Code, Helix); it needs
    ``pip install 'motiontool[lsp]'``.
    """
    require("pygls", "lsp", "motiontool server")
    from motiontool.cli import lsp

    Resolver(config=config, isolated=isolated)  # a bad --config fails now, not in the editor
    # The checks of each robot, checks and step, kept from one version to the next: what they
    # found at the configurations an edit left as they were is not found again.
    kept: dict[tuple[str, tuple[str, ...] | None, int | None], RobotChecks] = {}
    # Each document's reader, which reads a new version from the edit on (the last ones used).
    readers: dict[Path, Rereader] = {}

    def lint(
        path: Path, data: bytes, superseded: Callable[[], bool]
    ) -> tuple[FileReport, RobotSpec | None]:
        # Read afresh each time: an edited pyproject.toml applies to the next keystroke.
        resolver = Resolver(config=config, isolated=isolated)
        cache = None if no_cache else FindingsCache(read_only=not _saved(path, data))

        def checks(robot: str, names: tuple[str, ...] | None, step: int | None) -> RobotChecks:
            key = (robot, names, step)
            if key not in kept:
                kept[key] = robot_checks(
                    robot, names, step, tolerance=DEFAULT_PENETRATION_TOLERANCE_MM, cache=cache
                )
            kept[key].cache = cache
            kept[key].on_check = stop  # between checks: a superseded version stops there
            return kept[key]

        def stop(_step: str) -> None:
            if superseded():
                raise lsp.Superseded

        reader = readers.pop(path, None) or Rereader()
        readers[path] = reader  # the last one used last
        while len(readers) > _READERS:
            del readers[next(iter(readers))]
        return lint_document(path, data, resolver, Overrides(), checks, reader)

    lsp.build_server(lint).start_io()


_READERS = 16
"""Documents whose last version the server keeps to read the next one from the edit on
(:mod:`motiontool.motionfmt.reread`): those edited last."""


def _saved(path: Path, data: bytes) -> bool:
    """Whether ``data`` is what the file at ``path`` holds: text as saved is stored in the
    findings cache (the hook that checks the file next finds it there), text being typed is
    only looked up (a version a keystroke would fill it). Small files only: the cache keeps no
    other."""
    try:
        small = len(data) <= MAX_BYTES and path.stat().st_size == len(data)
        return small and path.read_bytes() == data
    except OSError:
        return False
