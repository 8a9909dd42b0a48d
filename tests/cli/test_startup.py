"""Start-up: ``motiontool --help`` and ``motiontool validate`` import only what they need
(each command is imported when it runs, ``cli/app.py``), and the collision check imports
Pinocchio only for pairs numpy cannot clear (the robot's tables kept on disk,
``kinematics/tables_cache.py``). What a process imported is read from its ``sys.modules``."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
import typer

from motiontool.cli.app import _COMMANDS, app

#: Run the CLI with the arguments given, then print what the process imported, as JSON.
_RUN = (
    "import json, sys\n"
    "from motiontool.cli.__main__ import main\n"
    "sys.argv[0] = 'motiontool'\n"
    "try:\n"
    "    main()\n"
    "except SystemExit:\n"
    "    pass\n"
    "print(json.dumps(sorted(sys.modules)), file=sys.stderr)\n"
)

#: Modules no start-up path of ``--help`` or ``validate`` needs.
_NEVER = (
    "motiontool.sim",
    "motiontool.cli.play",
    "motiontool.cli.batch",
    "motiontool.cli.convert",
    "motiontool.cli.concat",
    "motiontool.cli.server",
    "motiontool.cli.rule",
    "motiontool.motionfmt.convert",
    "xml.sax",  # kinematics.export quotes attributes with it, only when it exports
    "pinocchio",
    "mujoco",
    "pyarrow",
)

SMALL = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,Pose1,0\n00:00:500,Pose2,0.5\n"


def _imported(args: list[str], cwd: Path) -> tuple[set[str], str]:
    env = {k: v for k, v in os.environ.items() if k != "NO_COLOR"}
    env["XDG_CACHE_HOME"] = str(cwd / "cache")
    proc = subprocess.run(
        [sys.executable, "-c", _RUN, *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        check=False,
    )
    modules = json.loads(proc.stderr.strip().splitlines()[-1])
    return set(modules), proc.stdout


def _loaded(modules: set[str], names: tuple[str, ...]) -> list[str]:
    return [n for n in names if any(m == n or m.startswith(n + ".") for m in modules)]


def test_importing_the_cli_imports_no_command(tmp_path: Path) -> None:
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            "import json, sys, motiontool.cli.app; print(json.dumps(sorted(sys.modules)))",
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    modules = set(json.loads(proc.stdout))
    commands = [f"motiontool.cli.{module}" for module, _fn, _summary in _COMMANDS.values()]
    assert _loaded(modules, (*_NEVER, *commands, "numpy", "motiontool.kinematics")) == []


def test_help_lists_every_command_without_importing_one(tmp_path: Path) -> None:
    modules, out = _imported(["--help"], tmp_path)
    assert _loaded(modules, (*_NEVER, "motiontool.cli.validate", "numpy")) == []
    for name in _COMMANDS:
        assert f"  {name} " in out


@pytest.mark.needs("kinematics")
def test_validate_imports_neither_other_commands_nor_pinocchio_once_the_tables_are_stored(
    tmp_path: Path,
) -> None:
    (tmp_path / "small.motion").write_bytes(SMALL)
    cold, cold_out = _imported(["validate", "small.motion"], tmp_path)
    assert "pinocchio" in cold  # the first run builds the robot's tables, and stores them
    warm, warm_out = _imported(["validate", "small.motion"], tmp_path)
    assert warm_out == cold_out
    assert "collision" in warm_out
    assert _loaded(warm, _NEVER) == []
    assert "motiontool.cli.validate" in warm
    # No configuration file to read, no file to write, no time to retime; one block of
    # configurations: no thread pool; no masked arrays (np.unique imports numpy.ma); no
    # random numbers (the collision check's row hashes have their own fixed weights); no
    # document (a clean file gets no stretch fix to write).
    unused = ("tomllib", "tempfile", "fractions", "concurrent.futures", "numpy.ma", "numpy.random")
    unused += ("motiontool.motionfmt.document",)
    # Of the Pinocchio adapter, the stored tables alone: not its Protocols or its callers.
    pinocchio_side = ("api", "model", "configuration", "balance", "self_collision")
    unused += tuple(f"motiontool.kinematics._pinocchio.{m}" for m in pinocchio_side)
    unused += ("motiontool.kinematics.mirror",)  # no Left/Right sibling to compare with
    unused += ("zipfile",)  # the stored tables are .npy arrays one after another, no archive
    assert _loaded(warm, unused) == []


def test_the_syntax_level_of_a_small_file_imports_no_numpy_and_one_report_writer(
    tmp_path: Path,
) -> None:
    (tmp_path / "small.motion").write_bytes(SMALL)
    modules, out = _imported(["validate", "--robot", "none", "small.motion"], tmp_path)
    assert "checked 1 file: 0 errors" in out
    assert _loaded(modules, _NEVER) == []
    # Read without arrays; no robot fix to plan, no robot model to parse; the text report's
    # writer alone (each format's module is imported when a report is written in it).
    unused = ("numpy", "motiontool.kinematics.robot_fixes", "xml.etree")
    writers = ("json_report", "sarif", "github", "gitlab", "junit")
    assert _loaded(modules, (*unused, *(f"motiontool.cli.reports.{w}" for w in writers))) == []
    assert "motiontool.cli.reports.text" in modules
    # Of kinematics, the tables the help texts list (the checks' registry, the robots' names)
    # and no check, robot spec or findings cache; of motionfmt, the reader and the validation,
    # not the document, the player or the writer; no digest, no JSON writer (this harness
    # imports json itself).
    light = {
        "motiontool.kinematics",
        "motiontool.kinematics.builtin_robots",
        "motiontool.kinematics.checks",
        "motiontool.kinematics.checks.registry",
        "motiontool.kinematics.checks.wording",
    }
    assert {m for m in modules if m.startswith("motiontool.kinematics")} == light
    library = ("document", "player", "writer", "reread", "fixes")  # a clean file: no fix to make
    library = tuple(f"motiontool.motionfmt.{m}" for m in library)
    # No --fix, --statistics or configuration file: no fixer, statistics writer or TOML.
    others = ("motiontool.disk_cache", "motiontool.cli.jsontext", "hashlib", "tomllib")
    others += ("motiontool.cli.fixing", "motiontool.cli.reports.statistics")
    assert _loaded(modules, (*library, *others)) == []


def test_a_configuration_read_before_is_used_without_a_toml_parser(tmp_path: Path) -> None:
    """The hook in a configured repository: the second run takes the configuration's table
    from the cache (``cli/config_cache.py``), importing no TOML parser and no digest."""
    (tmp_path / "small.motion").write_bytes(SMALL)
    (tmp_path / "pyproject.toml").write_text(
        '[project]\nname = "robot-motions"\n\n[tool.motiontool]\nignore = ["MT206"]\n'
    )
    first, out = _imported(["validate", "--robot", "none", "small.motion"], tmp_path)
    assert "tomllib" in first and "checked 1 file: 0 errors" in out
    again, out_again = _imported(["validate", "--robot", "none", "small.motion"], tmp_path)
    assert out_again == out
    assert _loaded(again, ("tomllib", "motiontool.motionfmt.structured_text", "hashlib")) == []


def test_the_summaries_in_the_command_table_are_the_commands_own() -> None:
    root = typer.main.get_command(app)
    assert isinstance(root, typer.core.TyperGroup)
    lazy_help = root.get_help(typer.Context(root, info_name="motiontool"))
    for name, (_module, _fn, summary) in _COMMANDS.items():
        command = root.commands[name]  # imports and builds it
        first = " ".join((command.help or "").split("\n\n")[0].split())
        assert first.startswith(summary), name
        assert summary == first or len(summary) >= 80, name  # enough for any terminal
    # With every command built, --help lists them from their own help: the same text.
    assert root.get_help(typer.Context(root, info_name="motiontool")) == lazy_help
