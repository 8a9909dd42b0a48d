"""What the process is given, beyond its arguments: standard streams that are closed, and
the signals that end it (SIGTERM from ``docker stop`` or a CI timeout, SIGHUP from a closed
terminal). Every case runs the installed console script as a subprocess."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

SCRIPT = str(Path(sys.executable).parent / "motiontool")
HEAD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,Pose1,0,0\n00:00:160,Pose2,0.2,0.1\n"


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "in.motion").write_bytes(HEAD)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    (tmp_path / "tmp").mkdir()  # the tool's temporary folders (batch spool, recordings, bags)
    monkeypatch.setenv("TMPDIR", str(tmp_path / "tmp"))
    return tmp_path


def closed(redirect: str, *args: str) -> subprocess.CompletedProcess[bytes]:
    """``motiontool ARGS`` with a standard stream closed by the shell (``>&-``, ``2>&-``,
    ``<&-``), the others captured."""
    return subprocess.run(
        ["sh", "-c", f'exec "$@" {redirect}', "sh", SCRIPT, *args],
        capture_output=True,
        check=False,
    )


@pytest.mark.parametrize(
    "line",
    [["-V"], ["codes"], ["validate", "in.motion"], ["sample", "in.motion"]],
    ids=lambda c: c[0],
)
def test_a_closed_stdout_is_one_line_and_exit_2(here: Path, line: list[str]) -> None:
    done = closed(">&-", *line)
    assert done.returncode == 2, done.stderr
    assert done.stderr == b"motiontool: error: cannot write to standard output: it is closed\n"


def test_a_closed_stdout_is_no_error_for_a_command_that_writes_nothing_there(here: Path) -> None:
    done = closed(">&-", "validate", "in.motion", "-f", "json", "-o", "report.json")
    assert done.returncode == 0, done.stderr
    assert json.loads((here / "report.json").read_bytes())["summary"]
    assert b"Traceback" not in done.stderr


def test_a_file_opened_while_stdout_is_closed_gets_no_other_output(here: Path) -> None:
    """With descriptor 1 closed, the first file opened would take its number: the tool holds
    it on the null device, so that nothing meant for standard output lands in the file."""
    done = closed(">&-", "sample", "in.motion", "-o", "out.csv")
    assert done.returncode == 0, done.stderr
    assert (here / "out.csv").read_bytes().startswith(b"time_ms,HeadYaw,HeadPitch\n")
    done = closed(">&-", "mirror", "in.motion", "-o", "out.motion")  # it prints a summary
    assert done.returncode == 2
    assert done.stderr.endswith(
        b"motiontool: error: cannot write to standard output: it is closed\n"
    )
    assert (here / "out.motion").read_bytes().startswith(b"#WEBOTS_MOTION,V1.0,HeadYaw,")


@pytest.mark.parametrize(
    ("line", "code"),
    [(["-V"], 0), (["validate", "missing.motion"], 2), (["validate", "in.motion"], 0)],
    ids=["version", "missing", "clean"],
)
def test_a_closed_stderr_changes_no_exit_code(here: Path, line: list[str], code: int) -> None:
    done = closed("2>&-", *line)
    assert done.returncode == code
    if line == ["-V"]:
        assert done.stdout.startswith(b"motiontool ")


def test_a_closed_stdin_is_one_line(here: Path) -> None:
    done = closed("<&-", "validate", "-")
    assert done.returncode == 2
    assert done.stderr == (
        b"motiontool: error: cannot read '-' (<stdin>): there is no standard input\n"
    )
    assert closed("<&-", "validate", "in.motion").returncode == 0


def _lsp(*messages: dict[str, object]) -> bytes:
    out = b""
    for message in messages:
        body = json.dumps({"jsonrpc": "2.0", **message}).encode()
        out += b"Content-Length: %d\r\n\r\n" % len(body) + body
    return out


@pytest.mark.needs("lsp")
def test_the_server_exits_0_after_shutdown_and_exit(here: Path) -> None:
    """The LSP client's clean end: ``shutdown``, then ``exit``; the server closes its stdout
    itself before it returns."""
    talk = _lsp(
        {"id": 1, "method": "initialize", "params": {"capabilities": {}}},
        {"method": "initialized", "params": {}},
        {"id": 2, "method": "shutdown"},
        {"method": "exit"},
    )
    done = subprocess.run(
        [SCRIPT, "server"], input=talk, capture_output=True, check=False, timeout=60
    )
    assert (done.returncode, done.stderr) == (0, b"")
    assert b'"id": 2' in done.stdout or b'"id":2' in done.stdout


def _big_motion(path: Path) -> None:
    """A 10-minute motion of 15,000 poses: resampled every 1 ms, 21 MB to write."""
    rows = "".join(f"{t},P,{t % 1000 / 1000},{t % 700 / 1000}\n" for t in range(0, 600000, 40))
    path.write_text(f"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n{rows}")


def _wait_for(found: Callable[[], object], proc: subprocess.Popen[bytes]) -> None:
    """Wait until ``found()`` (at most 2 minutes); the process must still run."""
    deadline = time.monotonic() + 120
    while not found():
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            _, err = proc.communicate()
            pytest.fail(f"it ended (or never got there) before the signal: {err[-300:]!r}")
        time.sleep(0.01)


def _debris(folder: Path) -> list[str]:
    return sorted(str(p) for p in folder.rglob("*") if p.name.endswith(".tmp"))


@pytest.mark.parametrize(
    ("signum", "code", "word"),
    [(signal.SIGTERM, 143, "terminated"), (signal.SIGHUP, 129, "hangup")],
    ids=["SIGTERM", "SIGHUP"],
)
def test_a_signal_mid_write_removes_the_temporary_file(
    here: Path, signum: int, code: int, word: str
) -> None:
    """``docker stop`` or a CI timeout while ``resample -o`` writes its 21 MB: the temporary file
    beside the output goes, the output is not created, one line says why, exit 128 + N."""
    _big_motion(here / "big.motion")
    proc = subprocess.Popen(
        [SCRIPT, "resample", "big.motion", "--step", "1", "-o", "out.motion"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    _wait_for(lambda: _debris(here), proc)
    proc.send_signal(signum)
    _, err = proc.communicate(timeout=60)
    assert (proc.returncode, err.decode()) == (code, f"motiontool: error: {word}\n")
    assert _debris(here) == [] and not (here / "out.motion").exists()
    assert list((here / "tmp").iterdir()) == []


@pytest.mark.needs("sim")
def test_a_terminated_play_removes_its_temporary_recording(here: Path) -> None:
    """A recording is gathered in a temporary folder while the motion plays: SIGTERM then
    removes it."""
    rows = "".join(f"{t},P,{t % 1000 / 2000},{t % 700 / 2000}\n" for t in range(0, 120000, 400))
    (here / "long.motion").write_text(f"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n{rows}")
    proc = subprocess.Popen(
        [SCRIPT, "play", "long.motion", "--headless", "--rrd", "out"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    _wait_for(lambda: list((here / "tmp").glob("motiontool-*")), proc)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert (proc.returncode, err.decode()) == (143, "motiontool: error: terminated\n")
    assert [str(p) for p in (here / "tmp").rglob("*")] == [] and _debris(here) == []
    assert not (here / "out").exists()


def _children(pid: int) -> list[int]:
    text = Path(f"/proc/{pid}/task/{pid}/children").read_text()
    return [int(p) for p in text.split()]


def _running(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.needs("sim")
@pytest.mark.slow
@pytest.mark.parametrize("group", [False, True], ids=["parent", "group"])
def test_a_terminated_batch_stops_its_workers_and_leaves_no_debris(here: Path, group: bool) -> None:
    """SIGTERM to the batch alone (``docker stop``, ``kill PID``) or to its process group
    (``timeout``): exit 143 with one line, no worker left running, no temporary file left in
    the cache or beside the report, and the runs done so far stay in the cache."""
    cache = here / "cache-dir"
    line = ["batch", "in.motion", "--samples", "400", "--perturb", "friction=0.8:1.2"]
    proc = subprocess.Popen(
        [SCRIPT, *line, "--jobs", "2", "--cache-dir", str(cache), "--json", "report.json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    try:
        _wait_for(lambda: len(list(cache.rglob("*.json"))) >= 2, proc)
        workers = _children(proc.pid)
        assert workers
        if group:
            os.killpg(proc.pid, signal.SIGTERM)
        else:
            proc.send_signal(signal.SIGTERM)
        code = proc.wait(timeout=60)
        deadline = time.monotonic() + 10
        while any(_running(w) for w in workers) and time.monotonic() < deadline:
            time.sleep(0.05)
        left = [w for w in workers if _running(w)]
    finally:  # a worker left running holds stderr open: communicate() would wait for it
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        _, err = proc.communicate()
    assert (code, err.decode()) == (143, "motiontool: error: terminated\n")
    assert left == []
    assert _debris(here) == [] and not (here / "report.json").exists()
    assert list((here / "tmp").iterdir()) == []
    assert len(list(cache.rglob("*.json"))) >= 2


# Text from a file or an option, echoed in a message -------------------------------------------

HOSTILE = (
    b"#WEBOTS_MOTION,V1.0,Head\x1b[31mYaw,HeadPitch\n"
    b"0,P\x1b]0;pwned\x07,0,0x\x1b[2J\n"
    b"40,P2,abc\x1b[0m,0\n"
)


@pytest.mark.parametrize("form", ["text", "github"])
def test_control_characters_from_a_file_are_shown_escaped(here: Path, form: str) -> None:
    (here / "esc.motion").write_bytes(HOSTILE)
    done = subprocess.run(
        [SCRIPT, "validate", "esc.motion", "-f", form], capture_output=True, check=False
    )
    assert done.returncode == 1, done.stderr
    out = done.stdout + done.stderr
    assert not [c for c in out if c < 0x20 and c != 0x0A], out
    assert b"Head\\x1b[31mYaw" in out and b"abc\\x1b[0m" in out


def test_json_keeps_the_exact_text(here: Path) -> None:
    (here / "esc.motion").write_bytes(HOSTILE)
    done = subprocess.run(
        [SCRIPT, "validate", "esc.motion", "-f", "json"], capture_output=True, check=False
    )
    messages = [d["message"] for f in json.loads(done.stdout)["files"] for d in f["diagnostics"]]
    assert any("Head\x1b[31mYaw" in m for m in messages), messages


def test_a_long_name_is_capped_in_every_message(here: Path) -> None:
    (here / "long.motion").write_bytes(b"#WEBOTS_MOTION,V1.0," + b"H" * 4000 + b"\n0,P,0\n")
    done = subprocess.run(
        [SCRIPT, "validate", "long.motion", "--robot", "nao"], capture_output=True, check=False
    )
    lines = done.stdout.decode().splitlines()
    assert any("unknown joint 'HHH" in line for line in lines), lines
    assert max(len(line) for line in lines if "hint" not in line) < 200, lines


@pytest.mark.needs("sim")
def test_a_long_option_value_is_capped_in_the_error_line(here: Path) -> None:
    done = subprocess.run(
        [SCRIPT, "batch", "in.motion", "--expect", "a" * 5000], capture_output=True, check=False
    )
    err = done.stderr.decode()
    assert done.returncode == 2 and err.startswith("motiontool: error: expectation 'aaa")
    assert err.count("\n") == 1 and "a" * 81 not in err and len(err) < 600, err


class _Stop(BaseException):
    """What SIGTERM raises in the tests below (its handler)."""


@contextlib.contextmanager
def _sigterm_raises_stop() -> Iterator[None]:
    """SIGTERM's handler raises :class:`_Stop` (then the handler before it again); the block
    must end by it."""

    def stop(signum: int, frame: object) -> None:
        raise _Stop

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        with pytest.raises(_Stop):
            yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def test_a_signal_just_after_the_temporary_file_is_made_leaves_none(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The temporary file and the ``try`` that removes it are made as one step: a signal that
    comes between them is held until the removal is in place (it left ``.out.txt.XXXX.tmp``)."""
    import tempfile

    from motiontool.motionfmt.fileio import atomic_write

    real = tempfile.mkstemp

    def mkstemp_then_signal(*args: object, **kwargs: object) -> tuple[int, str]:
        made = real(*args, **kwargs)  # type: ignore[call-overload]
        os.kill(os.getpid(), signal.SIGTERM)  # its handler runs now, unless it is held
        return made  # type: ignore[no-any-return]

    monkeypatch.setattr(tempfile, "mkstemp", mkstemp_then_signal)
    with _sigterm_raises_stop():
        atomic_write(tmp_path / "out.txt", b"data")
    assert list(tmp_path.iterdir()) == []


def test_a_signal_just_after_a_temporary_folder_is_made_leaves_none(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The recording's, a batch's and a shipped run's temporary folders are made with their
    removal armed in one step: SIGTERM right after ``mkdtemp`` left an empty ``motiontool-rrd-*``
    (seen once in CI under load)."""
    import tempfile

    from motiontool.motionfmt.fileio import temporary_folder

    real = tempfile.mkdtemp

    def mkdtemp_then_signal(suffix: str | None, prefix: str | None, _dir: object) -> str:
        made = real(suffix, prefix, str(tmp_path))
        os.kill(os.getpid(), signal.SIGTERM)  # its handler runs now, unless it is held
        return made  # type: ignore[no-any-return]

    monkeypatch.setattr(tempfile, "mkdtemp", mkdtemp_then_signal)
    with _sigterm_raises_stop():
        temporary_folder("motiontool-rrd-")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.needs("sim")
def test_a_joint_name_play_ignores_is_shown_escaped(here: Path) -> None:
    (here / "esc.motion").write_bytes(
        b"#WEBOTS_MOTION,V1.0,HeadYaw,Bad\x1b[2JName\n0,P1,0,0\n160,P2,0.2,0\n"
    )
    done = subprocess.run(
        [SCRIPT, "play", "esc.motion", "--headless", "--robot", "nao"],
        capture_output=True,
        check=False,
    )
    assert b"motiontool: warning: joint 'Bad\\x1b[2JName' is not a motor" in done.stderr
    assert b"\x1b" not in done.stderr, done.stderr


def test_start_up_runs_without_collecting_and_the_command_with_the_collector_on(
    here: Path,
) -> None:
    """The console script turns the garbage collector off before its imports; the command runs
    with it on, what start-up made frozen (out of its sight). Called in process with the
    collector on (a test, a library), :func:`process.started` leaves it as it is."""
    script = (
        "import gc\n"
        "from motiontool.cli import process\n"
        "process.started()\n"
        "assert gc.isenabled() and gc.get_freeze_count() == 0\n"
        "process.start_up_uncollected()\n"
        "assert not gc.isenabled()\n"
        "process.started()\n"
        "assert gc.isenabled() and gc.get_freeze_count() > 1000\n"
    )
    subprocess.run([sys.executable, "-c", script], check=True)
    ran = subprocess.run(
        [sys.executable, "-m", "motiontool.cli", "validate", "in.motion"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert (ran.returncode, ran.stderr) == (0, "")
    assert "checked 1 file: 0 errors" in ran.stdout


def test_without_a_home_directory_the_caches_are_off(here: Path) -> None:
    """No ``XDG_CACHE_HOME``, no ``HOME`` and a user the system does not know (a container run
    as an arbitrary user id): Python finds no home directory, and every cache is off, the
    configuration's, the findings', the robot tables' included, instead of a traceback."""
    script = (
        "import pathlib, sys\n"
        "def home(cls):\n"
        "    raise RuntimeError('Could not determine home directory.')\n"
        "pathlib.Path.home = classmethod(home)\n"
        "from motiontool.cli.__main__ import main\n"
        "sys.argv[0] = 'motiontool'\n"
        "main()\n"
    )
    (here / "motiontool.toml").write_text('ignore = ["MT206"]\n')
    env = {k: v for k, v in os.environ.items() if k not in ("XDG_CACHE_HOME", "HOME")}
    env.pop("MOTIONTOOL_NO_CACHE", None)
    for args in (["validate", "in.motion"], ["validate", "--robot", "none", "in.motion"]):
        for _ in range(2):  # a second run finds nothing kept either
            ran = subprocess.run(
                [sys.executable, "-c", script, *args], capture_output=True, text=True, env=env
            )
            assert (ran.returncode, ran.stderr) == (0, ""), ran.stderr
            assert "checked 1 file: 0 errors" in ran.stdout
    ran = subprocess.run(
        [sys.executable, "-c", script, "cache", "info"], capture_output=True, text=True, env=env
    )
    assert (ran.returncode, ran.stderr) == (0, "")
    assert ran.stdout.count("/dev/null/motiontool/") == 4
