"""Outputs that are not plain files: character devices, FIFOs, symlinks, ``/dev/fd/N``, ``-``.

Every option that writes a file writes a regular file atomically (a temporary file, then a
rename), through a symlink to its target; it writes straight through a device, a FIFO or a
descriptor and never replaces it. The device nodes are made by the tests themselves (``mknod``
needs root, which CI has): never the machine's own ``/dev/null`` or ``/dev/full``.
"""

from __future__ import annotations

import os
import stat
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from conftest import dev_module
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.kinematics.robots import load_robot

runner = CliRunner()
SCRIPT = str(Path(sys.executable).parent / "motiontool")

HEAD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,Pose1,0,0\n00:00:160,Pose2,0.2,0.1\n"


_WRITERS_MODULE = dev_module("writers")
"""dev/writers.py, the one list of output options (dev/hostile.py reads it too)."""
WRITERS: list[list[str]] = _WRITERS_MODULE.WRITERS
IDS = [" ".join(a for a in c if a not in ("in.motion", "OUT")) for c in WRITERS]


def extras_of(line: list[str]) -> list[str]:
    """The extras a writer's command line needs beyond the core (tests/conftest.py skips it
    without them)."""
    by_command = {"play": "sim", "batch": "sim", "plot": "plot", "generate": "kinematics"}
    by_word = {"--rrd": "rerun", "--bag": "ros", "--plot": "plot", "--urdf": "kinematics"}
    by_word["rosbag"] = "ros"
    found = {by_command[line[0]]} if line[0] in by_command else set()
    return sorted(found | {extra for word, extra in by_word.items() if word in line})


#: One parameter per writer, marked with the extras it needs.
WRITER_PARAMS = [
    pytest.param(line, id=name, marks=pytest.mark.needs(*extras_of(line)))
    for line, name in zip(WRITERS, IDS, strict=True)
]


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def command(line: list[str], out: str) -> list[str]:
    return [out if a == "OUT" else a for a in line]


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "in.motion").write_bytes(HEAD)
    (tmp_path / "other.motion").write_bytes(HEAD)
    model = load_robot("ur5e").model_path
    (tmp_path / "model.xml").write_bytes(model.read_bytes())
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    return tmp_path


def make_device(path: Path, minor: int) -> Path:
    """A character device node of the memory driver (1, minor): 3 is null, 7 is full."""
    try:
        os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, minor))
    except PermissionError:
        pytest.skip("mknod needs root (CI runs as root)")
    return path


def test_writers_cover_every_output_option() -> None:
    """Every command option that takes a path to write is in WRITERS (a new one must join)."""
    import typer.main

    group = typer.main.get_command(app)
    written = {"--output", "--json", "--rrd", "--junit", "--markdown", "--plot", "--mjcf"}
    written |= {"--urdf", "--bag", "--send-script"}
    folders = {"--rrd-dir", "--cache-dir"}
    found = set()
    stack = [group]
    while stack:
        cmd = stack.pop()
        stack.extend(getattr(cmd, "commands", {}).values())
        for p in cmd.params:
            if p.name and p.opts[0] in written | folders:
                found.add(p.opts[0])
            elif p.opts[0] in ("--config", "--joint-map", "--world", "--after"):  # files read
                continue
            elif "path" in f"{p.type} {p.type.name}".lower() and p.opts[0].startswith("--"):
                pytest.fail(f"{cmd.name} {p.opts[0]}: a path option this test does not know")
    assert found == written | folders
    assert {_WRITERS_MODULE.written_option(c) for c in WRITERS} == written | {"OUT"}


@pytest.mark.parametrize("line", WRITER_PARAMS)
def test_a_character_device_is_written_through_not_replaced(here: Path, line: list[str]) -> None:
    null = make_device(here / "null", 3)
    code, _, err = invoke(*command(line, "null"))
    assert code in (0, 1), err
    assert stat.S_ISCHR(null.lstat().st_mode) and null.lstat().st_rdev == os.makedev(1, 3)
    assert not [p.name for p in here.iterdir() if p.name.startswith(".null.")]


@pytest.mark.parametrize("line", WRITER_PARAMS)
def test_a_full_device_is_a_full_disk(here: Path, line: list[str]) -> None:
    full = make_device(here / "full", 7)
    code, _, err = invoke(*command(line, "full"))
    assert code == 2
    assert err.endswith("cannot write 'full': No space left on device\n")
    assert err.count("\n") == 1 and stat.S_ISCHR(full.lstat().st_mode)


@pytest.mark.parametrize("line", WRITER_PARAMS)
def test_a_symlink_stays_a_link_and_its_target_gets_the_data(here: Path, line: list[str]) -> None:
    (here / "sub").mkdir()
    target = here / "sub" / "target"
    target.write_bytes(b"stale")
    target.chmod(0o640)
    (here / "link").symlink_to("sub/target")
    code, _, err = invoke(*command(line, "link"))
    assert code in (0, 1), err
    assert (here / "link").is_symlink() and os.readlink(here / "link") == "sub/target"
    assert target.read_bytes() not in (b"", b"stale")
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    assert sorted(p.name for p in (here / "sub").iterdir()) == ["target"]  # no temporary left


def test_a_dangling_symlink_creates_its_target(here: Path) -> None:
    (here / "link").symlink_to("made/report.json")
    assert invoke("validate", "in.motion", "-f", "json", "-o", "link")[0] == 0
    assert (here / "link").is_symlink() and (here / "made" / "report.json").read_bytes()


@pytest.mark.parametrize("line", WRITER_PARAMS)
def test_a_fifo_is_written_through_to_its_reader(here: Path, line: list[str]) -> None:
    fifo = here / "fifo"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
    reader.start()
    code, _, err = invoke(*command(line, "fifo"))
    reader.join(timeout=60)
    assert code in (0, 1), err
    assert stat.S_ISFIFO(fifo.lstat().st_mode) and got and got[0]


@pytest.mark.needs("kinematics")
def test_dash_is_stdout_everywhere(here: Path) -> None:
    code, out, _ = invoke("validate", "in.motion", "-f", "json", "-o", "-")
    assert code == 0 and out.startswith("{")
    code, out, _ = invoke("robots", "export", "model.xml", "--mjcf", "-")
    assert code == 0 and out.rstrip().endswith("</mujoco>")
    assert not (here / "-").exists()


def test_dev_fd_is_the_descriptor_the_shell_opened(here: Path) -> None:
    """``-o /dev/fd/N`` writes that descriptor, appending where it appends."""
    log = here / "log.txt"
    log.write_bytes(b"kept\n")
    with log.open("ab") as f:
        done = subprocess.run(
            [SCRIPT, "validate", "in.motion", "-o", f"/dev/fd/{f.fileno()}"],
            pass_fds=[f.fileno()],
            capture_output=True,
            check=False,
        )
    assert done.returncode == 0, done.stderr
    assert log.read_bytes().startswith(b"kept\nrobot: ")
    read, write = os.pipe()
    done = subprocess.run(
        [SCRIPT, "sample", "in.motion", "-o", "/dev/stdout"],
        stdout=write,
        capture_output=False,
        stderr=subprocess.PIPE,
        check=False,
    )
    os.close(write)
    with os.fdopen(read, "rb") as pipe:
        assert done.returncode == 0 and pipe.read().startswith(b"time_ms,HeadYaw")


@pytest.mark.parametrize(
    "line",
    [
        ["validate", "in.motion"],
        ["sample", "in.motion"],
        ["codes"],
        ["info", "in.motion"],
        ["mirror", "in.motion", "-o", "-"],
        ["robots"],
        ["diff", "in.motion", "other.motion"],
    ],
    ids=lambda c: c[0],
)
def test_stdout_on_a_full_disk_is_one_line_and_exit_2(here: Path, line: list[str]) -> None:
    full = make_device(here / "full", 7)
    with full.open("wb") as stdout:
        done = subprocess.run(
            [SCRIPT, *line], stdout=stdout, stderr=subprocess.PIPE, check=False, cwd=here
        )
    err = done.stderr.decode()
    assert done.returncode == 2, err
    assert err == "motiontool: error: cannot write to standard output: No space left on device\n"


def test_a_reader_that_goes_away_ends_quietly(here: Path) -> None:
    """``sample big.motion | head -1``: no traceback, the exit status of a SIGPIPE."""
    rows = b"".join(b"00:%02d:%03d,P,0.1,0.2\n" % divmod(t, 1000) for t in range(40, 60000, 40))
    (here / "long.motion").write_bytes(HEAD.splitlines(keepends=True)[0] + rows)
    proc = subprocess.Popen(
        [SCRIPT, "sample", "long.motion", "-t", "1"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        cwd=here,
    )
    assert proc.stdout is not None and proc.stderr is not None
    assert proc.stdout.readline().startswith(b"time_ms,")
    proc.stdout.close()
    with proc.stderr:
        err = proc.stderr.read()
    assert proc.wait(timeout=60) == 141 and err == b""


@pytest.mark.parametrize(
    ("line", "message"),
    [
        (
            ["play", "in.motion", "--headless", "--json", "X", "--rrd", "./X"],
            "--json and --rrd both write 'X'",
        ),
        (["batch", "in.motion", "--json", "X", "--markdown", "X"], "--json and --markdown"),
        (["batch", "in.motion", "--junit", "-", "--markdown", "-"], "--markdown and --junit"),
        (["batch", "in.motion", "--rrd-dir", "other.motion"], "--rrd-dir 'other.motion' is not"),
        (["batch", "in.motion", "--rrd-dir", "-"], "--rrd-dir '-' is not a folder"),
        (["batch", "in.motion", "--ray-address", "auto"], "use it with --executor ray"),
    ],
)
def test_conflicting_outputs_are_refused_before_anything_runs(
    here: Path, line: list[str], message: str
) -> None:
    code, out, err = invoke(*line)
    assert (code, out) == (2, ""), err
    assert message in err and err.count("\n") == 1
    assert not (here / "X").exists()


@pytest.mark.needs("sim")
def test_two_outputs_may_share_a_device(here: Path) -> None:
    make_device(here / "null", 3)
    code, _, err = invoke(
        "batch", "in.motion", "--no-cache", "--json", "null", "--markdown", "null"
    )
    assert code == 0, err


@pytest.mark.needs("sim")
def test_play_json_on_stdout_moves_the_text_report_to_stderr(here: Path) -> None:
    code, out, err = invoke("play", "in.motion", "--headless", "--json", "-")
    assert code == 0, err
    assert out.startswith("{") and "clean" in err


def float_options() -> list[tuple[list[str], str]]:
    """(command path, option) for every option of the tool that reads a float."""
    import typer.main
    from typer._click import types

    found = []
    stack: list[tuple[list[str], object]] = [([], typer.main.get_command(app))]
    while stack:
        path, cmd = stack.pop()
        for name, sub in getattr(cmd, "commands", {}).items():
            stack.append(([*path, name], sub))
        for p in getattr(cmd, "params", []):
            if isinstance(p.type, types.FloatParamType) and p.opts[0].startswith("--"):
                found.append((path, p.opts[0]))
    return sorted(found)


@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
@pytest.mark.parametrize(
    ("path", "option"), float_options(), ids=lambda x: " ".join(x) if isinstance(x, list) else x
)
def test_no_float_option_takes_nan_or_infinity(path: list[str], option: str, value: str) -> None:
    code, out, err = invoke(*path, f"{option}={value}", "in.motion")
    assert (code, out) == (2, ""), err
    assert err.startswith(f"motiontool: error: invalid value for '{option}'")
    assert "is not a finite number" in err or "not in the range" in err, err
    assert err.count("\n") == 1


def test_float_options_are_found() -> None:
    assert len(float_options()) >= 12


@pytest.mark.parametrize(
    ("line", "message"),
    [
        (
            ["validate", "--timestep", "abc", "in.motion"],
            "invalid value for '--timestep' / '-t': 'abc' is not a valid int range;"
            " see 'motiontool validate --help'",
        ),
        (["validate"], "missing argument 'paths'; see 'motiontool validate --help'"),
        (["info", "in.motion", "--bogus"], "no such option: --bogus; see 'motiontool info --help'"),
        (
            ["valdate"],
            "no such command 'valdate'. Did you mean 'validate'? see 'motiontool --help'",
        ),
        (["robots", "show", "nao", "-f", "csv"], "'csv' is not one of 'text', 'json'"),
        (["info", "in.motion", "-f", "csv"], "'csv' is not one of 'text', 'json'"),
        (
            ["sample", "in.motion", "-t", "99999999999999999999"],
            "not in the range 1<=x<=2147483647",
        ),
        pytest.param(
            ["play", "in.motion", "--headless", "--loop", "99999999999999999999"],
            "not in the range",
            marks=pytest.mark.needs("sim"),
        ),
        (["batch", "in.motion", "--timeout", "1e9"], "more than 604800 s (a week)"),
        (["batch", "in.motion", "--timeout", "inf"], "inf is not a finite number"),
        (["diff", "in.motion", "other.motion", "--tolerance", "nan"], "nan is not a finite"),
    ],
)
def test_option_errors_are_one_line_with_a_pointer_to_help(
    here: Path, line: list[str], message: str
) -> None:
    code, out, err = invoke(*line)
    assert (code, out) == (2, ""), err
    assert err.startswith("motiontool: error: ") and message in err, err
    assert err.count("\n") == 1


def test_info_and_robots_show_offer_only_what_they_accept() -> None:
    for line in (["info", "--help"], ["robots", "show", "--help"]):
        assert "csv" not in invoke(*line)[1]


@pytest.mark.needs("sim")
@pytest.mark.slow
def test_ctrl_c_in_batch_exits_130_without_a_traceback(here: Path) -> None:
    """Ctrl-C reaches the whole process group: the parent says 'interrupted' once and exits
    130, no worker prints a KeyboardInterrupt, and the runs done so far stay in the cache."""
    import signal
    import time

    cache = here / "cache-dir"
    line = ["batch", "in.motion", "--samples", "400", "--perturb", "friction=0.8:1.2"]
    # SIGINT at its default, as from a terminal: a test run started in the background (`&`,
    # nohup) inherits it ignored, and the batch would then ignore the Ctrl-C.
    default_sigint = (
        "import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); "
        "os.execv(sys.argv[1], sys.argv[1:])"
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", default_sigint, SCRIPT, *line, "--cache-dir", str(cache)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        cwd=here,
        start_new_session=True,
    )
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and len(list(cache.rglob("*.json"))) < 2:
        time.sleep(0.2)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert err.decode() == "motiontool: error: interrupted\n"
    assert len(list(cache.rglob("*.json"))) >= 2
    assert not [p for p in cache.rglob("*") if p.name.endswith(".tmp")]


def test_a_read_only_folder_is_refused_before_anything_runs(here: Path) -> None:
    ro = here / "ro"
    ro.mkdir()
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "ro,size=64k", "none", str(ro)], check=False
    )
    if done.returncode != 0:
        pytest.skip("mounting a read-only tmpfs needs root (CI runs as root)")
    try:
        for option in ("--rrd-dir", "--cache-dir"):
            code, out, err = invoke("batch", "in.motion", option, "ro")
            assert (code, out) == (2, ""), err
            assert err == "motiontool: error: cannot write in 'ro': Read-only file system\n"
        code, _, err = invoke("validate", "in.motion", "-o", "ro/report.txt")
        assert (code, err) == (
            2,
            "motiontool: error: cannot write 'ro/report.txt': Read-only file system\n",
        )
    finally:
        subprocess.run(["umount", str(ro)], check=True)


@pytest.mark.parametrize("line", WRITERS, ids=IDS)  # refused before any extra is used
def test_an_empty_path_is_a_usage_error(here: Path, line: list[str]) -> None:
    # '' is no file (pathlib reads it as '.'): one line, exit 2, nothing written.
    code, _, err = invoke(*command(line, ""))
    assert code == 2, err
    assert err.startswith("motiontool: error: ") and err.count("\n") == 1, err
    if "-o" in line:  # the shared --output options say what is wrong
        assert "an empty path names no file" in err, err
    assert {p.name for p in here.iterdir()} <= {"cache", "in.motion", "model.xml", "other.motion"}
