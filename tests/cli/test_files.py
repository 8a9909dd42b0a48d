"""Input and output files across every command: never over an input (same path, symlink, hard
link), unreadable files read like missing ones, '-' for stdin, --debug, short options, completion.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
import typer.core
import typer.main
from typer.testing import CliRunner

from motiontool import __version__
from motiontool.cli.app import app
from motiontool.kinematics.robots import load_robot, robot_choices

runner = CliRunner()

HEAD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,Pose1,0,0\n00:00:160,Pose2,0.2,0.1\n"
# Webots accepts it; the syntax level finds 1 error (nan), 5 warnings (a joint named twice,
# '2rad', a '*' over a segment, -9999999.9, the blank line) and 1 note (a '*' to the end).
MANY = (
    b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw,HeadPitch\n"
    b"00:00:000,P1,0,2rad,*\n00:00:080,P2,1,0,0.1\n00:00:120,P3,nan,0,0\n"
    b"00:00:150,P4,1,0,-9999999.9\n\n00:00:200,P5,0,0,0\n"
)


def invoke(*args: str, stdin: bytes | None = None) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args), input=stdin)
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "in.motion").write_bytes(HEAD)
    (tmp_path / "other.motion").write_bytes(HEAD)
    shutil.copy(load_robot("ur5e").model_path, tmp_path / "model.xml")
    monkeypatch.chdir(tmp_path)
    return tmp_path


# --------------------------------------------------------------------------- never over an input

# (command line, its input file, the option that names the output); OUT is the output's place.
WRITERS = [
    (["validate", "in.motion", "-o", "OUT"], "in.motion", "-o"),
    (["validate", ".", "--robot", "none", "-o", "OUT"], "in.motion", "-o"),  # found in a folder
    (["sample", "in.motion", "-o", "OUT"], "in.motion", "-o"),
    (["play", "in.motion", "--headless", "--json", "OUT"], "in.motion", "--json"),
    (["play", "other.motion", "in.motion", "--headless", "--rrd", "OUT"], "in.motion", "--rrd"),
    (["batch", "in.motion", "--json", "OUT"], "in.motion", "--json"),
    (["batch", "in.motion", "--junit", "OUT"], "in.motion", "--junit"),
    (["batch", "in.motion", "--markdown", "OUT"], "in.motion", "--markdown"),
    (["batch", "in.motion", "--rrd-dir", "OUT"], "in.motion", "--rrd-dir"),
    (["diff", "other.motion", "in.motion", "--plot", "OUT"], "in.motion", "--plot"),
    (["plot", "in.motion", "-o", "OUT"], "in.motion", "-o"),
    (["resample", "in.motion", "--step", "20", "-o", "OUT"], "in.motion", "-o"),
    (["retime", "in.motion", "--speed", "2", "-o", "OUT"], "in.motion", "-o"),
    (["robots", "export", "model.xml", "--mjcf", "OUT"], "model.xml", "--mjcf"),
    (["robots", "export", "model.xml", "--urdf", "OUT"], "model.xml", "--urdf"),
]


@pytest.mark.parametrize("link", ["same path", "symlink", "hard link"])
@pytest.mark.parametrize(("command", "source", "option"), WRITERS)
def test_no_command_writes_over_its_input(
    here: Path, command: list[str], source: str, option: str, link: str
) -> None:
    before = (here / source).read_bytes()
    inode = (here / source).stat().st_ino
    if link == "same path":
        out = source
    elif link == "symlink":
        out = "link.out"
        (here / out).symlink_to(source)
    else:
        out = "hard.out"
        os.link(here / source, here / out)
    code, stdout, err = invoke(*[out if a == "OUT" else a for a in command])
    assert (code, stdout) == (2, ""), err
    assert err.startswith(f"motiontool: error: {option} '{out}' is the input file")
    assert err.count("\n") == 1 and err.endswith("\n")
    assert (here / source).read_bytes() == before and (here / source).stat().st_ino == inode
    if link == "symlink":
        assert (here / out).is_symlink()


def test_a_new_or_unrelated_output_is_written(here: Path) -> None:
    (here / "old.csv").write_bytes(b"stale")
    for out in ("new.csv", "old.csv"):
        assert invoke("sample", "in.motion", "-o", out)[0] == 0
        assert (here / out).read_text().startswith("time_ms,HeadYaw,HeadPitch\n")
    assert (here / "in.motion").read_bytes() == HEAD


# --------------------------------------------------------------------------- unreadable input

READERS = [
    ["validate", "PATH"],
    ["info", "PATH"],
    ["sample", "PATH"],
    ["diff", "in.motion", "PATH"],
    ["plot", "PATH", "-o", "p.png"],
    ["resample", "PATH", "--step", "20", "-o", "r.motion"],
    ["retime", "PATH", "--speed", "2", "-o", "r.motion"],
    ["play", "PATH", "--headless"],
]
#: The extras a reader needs before it reads (a missing one is said first).
NEEDS = {"plot": ("plot",), "play": ("sim",)}


UNREADABLE = [
    ("missing.motion", "No such file or directory"),
    ("in.motion/x.motion", "Not a directory"),  # a parent that is a file: ENOTDIR
    ("folder.motion", "Is a directory, expected a .motion file"),
]


@pytest.mark.parametrize(
    ("command", "path", "reason"),
    [
        pytest.param(command, path, reason, marks=pytest.mark.needs(*NEEDS.get(command[0], ())))
        for command in READERS
        for path, reason in UNREADABLE
        if not (command[0] == "validate" and path == "folder.motion")  # validate searches it
    ],
    ids=lambda x: x[0] if isinstance(x, list) else None,
)
def test_an_unreadable_file_reads_like_a_missing_one(
    here: Path, command: list[str], path: str, reason: str
) -> None:
    (here / "folder.motion").mkdir()
    code, out, err = invoke(*[path if a == "PATH" else a for a in command])
    assert (code, out, err) == (2, "", f"motiontool: error: cannot read '{path}': {reason}\n")
    assert not (here / "r.motion").exists() and not (here / "p.png").exists()


@contextlib.contextmanager
def _unprivileged() -> Iterator[None]:
    """Root reads a file whatever its mode: run the block as 'nobody' (effective uid only, so
    the test gets root back), elsewhere as the user running the tests."""
    if os.geteuid() != 0:
        yield
        return
    os.seteuid(65534)
    try:
        yield
    finally:
        os.seteuid(0)


def test_a_file_without_read_permission(here: Path) -> None:
    locked = here / "locked.motion"
    locked.write_bytes(HEAD)
    locked.chmod(0)
    here.chmod(0o755)  # the folder stays searchable: only the file's mode stops the read
    with _unprivileged():
        results = [invoke(*c) for c in (["validate", "locked.motion"], ["info", "locked.motion"])]
    for result in results:
        assert result == (
            2,
            "",
            "motiontool: error: cannot read 'locked.motion': Permission denied\n",
        )


def _walked_folder(here: Path) -> None:
    """``m/``: a motion, a folder nobody may read, a dangling link and a link to itself."""
    (here / "m" / "ok").mkdir(parents=True)
    (here / "m" / "ok" / "a.motion").write_bytes(HEAD)
    (here / "m" / "locked").mkdir()
    (here / "m" / "locked" / "b.motion").write_bytes(HEAD)
    (here / "m" / "gone.motion").symlink_to("nowhere.motion")
    (here / "m" / "loop.motion").symlink_to("loop.motion")
    (here / "m" / "locked").chmod(0)
    here.chmod(0o755)
    (here / "m").chmod(0o755)
    (here / "m" / "ok").chmod(0o755)


@pytest.mark.parametrize(
    "command", [["validate"], ["batch", "--no-cache"], ["expect", "--infer"]], ids=lambda c: c[0]
)
def test_a_folder_walk_reports_what_it_cannot_read(here: Path, command: list[str]) -> None:
    """As ruff's E902: every entry of the search that cannot be read is named with its reason,
    and the exit is not 0 (it said 'checked 1 file' and exited 0)."""
    _walked_folder(here)
    for warm in ("m/ok", "missing.motion"):  # every module imported while root, who may
        invoke(*command, warm)  # read the interpreter's, runs it
    with _unprivileged():
        code, out, err = invoke(*command, "m")
    assert (code, out) == (2, ""), (err, out)
    assert err.startswith("motiontool: error: cannot read 3 entries under 'm': ")
    assert err.count("\n") == 1
    assert "'m/locked': Permission denied" in err
    assert "'m/gone.motion': No such file or directory (a symbolic link to 'nowhere.motion')" in err
    assert "'m/loop.motion': Too many levels of symbolic links" in err


def test_a_file_in_a_folder_nobody_may_read_cannot_be_read(here: Path) -> None:
    _walked_folder(here)
    for command in (["validate"], ["validate", "--fix"], ["info"], ["batch", "--no-cache"]):
        invoke(*command, "m/ok/a.motion")
        invoke(*command, "missing.motion")
        with _unprivileged():
            result = invoke(*command, "m/locked/b.motion")
        assert result == (
            2,
            "",
            "motiontool: error: cannot read 'm/locked/b.motion': Permission denied\n",
        ), command


def test_a_folder_nobody_may_list_is_named_alone(here: Path) -> None:
    _walked_folder(here)
    invoke("validate", "missing.motion")
    with _unprivileged():
        result = invoke("validate", "m/locked")
    assert result == (2, "", "motiontool: error: cannot read 'm/locked': Permission denied\n")


def test_an_os_error_no_command_foresaw_is_not_called_a_write(
    here: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The entry point's last resort for an OSError names the path, not a write it cannot
    know of: here a --config in a folder nobody may search (it said 'cannot write')."""
    from motiontool.cli.app import main

    _walked_folder(here)
    (here / "m" / "locked").chmod(0o755)
    (here / "m" / "locked" / "motiontool.toml").write_text("[lint]\n")
    (here / "m" / "locked").chmod(0)
    invoke("validate", "--config", "in.motion", "in.motion")
    invoke("validate", "missing.motion")
    monkeypatch.setattr(
        sys, "argv", ["motiontool", "validate", "--config", "m/locked/motiontool.toml", "in.motion"]
    )
    with _unprivileged(), pytest.raises(SystemExit) as ended:
        main()
    assert ended.value.code == 2
    assert capsys.readouterr().err == (
        "motiontool: error: cannot access 'm/locked/motiontool.toml': Permission denied\n"
    )


# --------------------------------------------------------------------------- --debug


def test_debug_prints_a_traceback_and_keeps_exit_2(here: Path) -> None:
    code, out, err = invoke("--debug", "retime", "in.motion", "--speed", "1e-9", "-o", "x.motion")
    assert (code, out) == (2, "")
    assert err.startswith("Traceback (most recent call last):")
    assert "TimeOverflowError" in err
    assert err.splitlines()[-1].startswith("motiontool: error: retiming at speed x1e-09")
    code, _, err = invoke("retime", "in.motion", "--speed", "1e-9", "-o", "x.motion")
    assert code == 2 and "Traceback" not in err and err.count("\n") == 1


def _script() -> str:
    script = shutil.which("motiontool", path=str(Path(sys.executable).parent))
    assert script, "the console script 'motiontool' is not installed next to this Python"
    return script


def test_debug_traceback_from_the_installed_script(here: Path) -> None:
    proc = subprocess.run(
        [_script(), "--debug", "validate", "missing.motion"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 2
    assert "Traceback (most recent call last):" in proc.stderr
    assert proc.stderr.endswith(
        "motiontool: error: cannot read 'missing.motion': No such file or directory\n"
    )


# --------------------------------------------------------------------------- '-': stdin


@pytest.mark.needs("sim")
def test_dash_reads_stdin_and_diagnostics_name_it(here: Path) -> None:
    bad = b"#WEBOTS_MOTION,V1.0,A\n0,a,abc\n"
    code, out, _ = invoke("validate", "--robot", "none", "-", stdin=bad)
    assert code == 1
    assert (
        out.splitlines()[1]
        == "<stdin>:2:5: error MT108: expected a number or '*' for A, found 'abc'"
    )
    code, out, _ = invoke("validate", "--robot", "none", "-f", "json", "-", "in.motion", stdin=HEAD)
    assert code == 0 and [f["path"] for f in json.loads(out)["files"]] == ["<stdin>", "in.motion"]
    code, out, _ = invoke("info", "-", stdin=HEAD)
    assert code == 0 and out.startswith("file        <stdin> (")
    code, out, _ = invoke("sample", "-", "-t", "80", stdin=HEAD)
    assert (code, out) == (0, "time_ms,HeadYaw,HeadPitch\n0,0.0,0.0\n80,0.1,0.05\n160,0.2,0.1\n")
    code, out, _ = invoke("diff", "-", "in.motion", stdin=HEAD)
    assert code == 0 and out.startswith("same: <stdin> and in.motion command the same motion")
    code, out, err = invoke("retime", "-", "--speed", "2", "-o", "-", stdin=HEAD)
    assert code == 0 and out.endswith("00:00:080,Pose2,0.2,0.1\n")
    assert err.startswith("retimed <stdin> -> stdout: speed x2")
    code, out, err = invoke("play", "-", "--headless", "--hold", "0", stdin=HEAD)
    assert code == 0 and out.startswith("<stdin> on nao: ")


def test_in_place_refuses_stdin(here: Path) -> None:
    for command in (["resample", "-", "--step", "20"], ["retime", "-", "--speed", "2"]):
        code, out, err = invoke(*command, "--in-place", stdin=HEAD)
        assert (code, out) == (2, "")
        assert err == (
            "motiontool: error: --in-place cannot replace standard input ('-'); "
            "give -o FILE, or -o - for stdout\n"
        )
    assert not (here / "-").exists()


# --------------------------------------------------------------------------- conventions

SHORT = {"--robot": "-r", "--timestep": "-t", "--output": "-o", "--format": "-f"}


def _commands() -> list[tuple[str, typer.core.TyperCommand | typer.core.TyperGroup]]:
    root = typer.main.get_command(app)
    found = []

    def walk(command: typer.core.TyperCommand | typer.core.TyperGroup, name: str) -> None:
        for sub_name, sub in getattr(command, "commands", {}).items():
            walk(sub, f"{name} {sub_name}".strip())
        if name:
            found.append((name, command))

    walk(root, "")
    return found


def test_short_options_mean_the_same_on_every_command() -> None:
    seen = set()
    for name, command in _commands():
        for param in command.params:
            opts = set(param.opts)
            for long, short in SHORT.items():
                if long in opts or short in opts:
                    assert {long, short} <= opts, f"{name}: {sorted(opts)} should be {long}/{short}"
                    seen.add((name, long))
    assert {("validate", "--timestep"), ("play", "--robot"), ("batch", "--timestep")} <= seen


def test_robot_and_timestep_options_share_their_help_and_choices() -> None:
    """One --robot help text with the one list of choices, one --timestep wording."""
    robots, timesteps = [], []
    for name, command in _commands():
        for param in command.params:
            if "--robot" in param.opts:
                robots.append(name)
                help_text = getattr(param, "help", "") or ""
                keywords = ("auto", "none") if "none:" in help_text else ("auto",)
                assert robot_choices(*keywords) in help_text, (name, help_text)
                assert "auto: the built-in robot that has the most" in help_text, name
            if "--timestep" in param.opts:
                timesteps.append(name)
                assert (getattr(param, "help", "") or "").startswith(
                    "Controller time step in ms"
                ), name
    assert {"validate", "play", "batch", "retime", "mirror", "concat", "scale", "plot"} <= set(
        robots
    )
    assert {
        "validate",
        "sample",
        "play",
        "batch",
        "retime",
        "concat",
        "scale",
        "plot",
        "diff",
    } <= set(timesteps)


ANY_INT = {"--seed"}
"""Int options that take any int: a seed (numpy's generators take one of any size)."""


def _int_options() -> list[tuple[str, str]]:
    return [
        (name, param.opts[0])
        for name, command in _commands()
        for param in command.params
        if param.param_type_name == "option"
        and param.type.name in ("integer", "int range")
        and not ANY_INT & set(param.opts)
    ]


@pytest.mark.parametrize(("command", "option"), _int_options())
def test_a_huge_int_is_refused_naming_the_option_and_its_range(
    here: Path, command: str, option: str
) -> None:
    """``resample --step 99999999999999999999`` raised OverflowError (a C long), ``batch
    --samples`` of it listed runs until memory ran out: every int option has a range, and a
    number outside it is a usage error, before the command runs."""
    args = ("in.motion", "out.motion")  # as many as any command takes (convert IN OUT)
    code, out, err = invoke(*command.split(), option, "99999999999999999999", *args)
    assert code == 2 and out == "", err
    assert err.startswith(f"motiontool: error: invalid value for '{option}'"), err
    assert "99999999999999999999 is not in the range" in err and err.count("\n") == 1, err


def test_int_options_are_found(here: Path) -> None:
    found = set(_int_options())
    assert {("resample", "--step"), ("batch", "--samples"), ("retime", "--duration")} <= found


def test_no_robot_fits_the_cli_names_the_robot_option(here: Path) -> None:
    # The library says "name the robot explicitly"; the CLI says how: --robot.
    (here / "hex.motion").write_bytes(b"#WEBOTS_MOTION,V1.0,leg0\n0,p,0\n100,q,1\n")
    choices = "nao, nao-v5, ur5e, a .urdf/.xml path, or erd:<name>"
    line = (
        "motiontool: error: no robot fits the motion: no built-in robot (nao, nao-v5, ur5e) has"
        f" any of its joints; name one with --robot ({choices})\n"
    )
    for args in (["retime", "--fit-limits"], ["mirror"]):
        assert invoke(*args, "hex.motion", "-o", "x.motion") == (2, "", line), args
    assert not (here / "x.motion").exists()


def test_version_short_option() -> None:
    assert invoke("-V") == (0, f"motiontool {__version__}\n", "")
    assert invoke("--version") == (0, f"motiontool {__version__}\n", "")


def test_shell_completion(here: Path) -> None:
    code, out, _ = invoke("--show-completion", "bash")
    assert code == 0 and "_MOTIONTOOL_COMPLETE=complete_bash" in out
    env = dict(
        os.environ,
        _MOTIONTOOL_COMPLETE="complete_bash",
        COMP_WORDS="motiontool val",
        COMP_CWORD="1",
    )
    proc = subprocess.run([_script()], env=env, capture_output=True, text=True, check=False)
    assert (proc.returncode, proc.stdout.split()) == (0, ["validate"])


def test_info_counts_what_validate_robot_none_finds(here: Path) -> None:
    (here / "many.motion").write_bytes(MANY)
    code, out, _ = invoke("validate", "--robot", "none", "-f", "json", "many.motion")
    summary = json.loads(out)["summary"]
    assert code == 1 and (summary["errors"], summary["warnings"], summary["notes"]) == (1, 5, 1)
    code, out, _ = invoke("info", "-f", "json", "many.motion")
    info = json.loads(out)
    assert code == 0 and info["schema_version"] == 2
    assert (info["errors"], info["warnings"], info["notes"]) == (1, 5, 1)
    code, out, _ = invoke("info", "many.motion")
    assert out.splitlines()[-1] == (
        "findings    1 error, 5 warnings, 1 note "
        "(syntax only; 'motiontool validate --robot none many.motion' lists them)"
    )
