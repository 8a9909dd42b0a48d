"""Hostile inputs against the installed ``motiontool``: outputs that are devices, FIFOs, links
and descriptors, a full disk (a ``/dev/full`` node this script makes), stdout that cannot be
written, a reader that goes away, Ctrl-C, huge and non-finite numbers, two outputs on one path,
a motion that plays for 23 days (under a 3 GiB memory limit), closed standard streams, SIGTERM
and SIGHUP mid-write (no temporary file, no worker left), folder searches over dangling links
and link loops, and names with ESC sequences or 4,000 characters echoed in messages.

Every case runs the real console script in a scratch folder and checks two things: no Python
traceback on stderr, and no special file replaced (a device node, a FIFO or a symlink is the
same kind of file, with the same target, afterwards). Prints one line per failure and a
closing count; exit 1 if anything failed. ``dev/test.sh`` runs it (CI too).

    python dev/hostile.py [--jobs 2]

Device nodes need root (``mknod``); without it those cases are left out, and said so.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import resource
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from writers import WRITERS  # dev/writers.py: this script's folder is on sys.path

from motiontool import exit_codes

ROOT = Path(__file__).resolve().parent.parent
SCRIPT = str(Path(sys.executable).parent / "motiontool")
MOTION = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,0\n00:00:160,P2,0.2,0.1\n"

# Numbers no option may take: refused by its range, in one line.
HUGE = [
    ["sample", "in.motion", "-t", "99999999999999999999"],
    ["sample", "in.motion", "--loop", "99999999999999999999"],
    ["play", "in.motion", "--headless", "--loop", "99999999999999999999"],
    ["play", "in.motion", "--headless", "--hold", "inf"],
    ["batch", "in.motion", "--timeout", "inf"],
    ["batch", "in.motion", "--timeout", "1e9"],
    ["batch", "in.motion", "--friction", "nan"],
    ["diff", "in.motion", "other.motion", "--tolerance", "nan"],
    ["retime", "in.motion", "--speed", "inf", "-o", "r.motion"],
    ["validate", "in.motion", "-t", "2147483648"],
    ["resample", "in.motion", "--step", "99999999999999999999", "-o", "X"],
    ["batch", "in.motion", "--samples", "99999999999999999999", "--perturb", "mass=1:2"],
    ["batch", "in.motion", "--jobs", "99999999999999999999"],
    ["concat", "in.motion", "other.motion", "--transition", "99999999999999999999", "-o", "X"],
    ["convert", "in.motion", "X", "--to", "naoqi", "--lead-in", "99999999999999999999"],
    # A perturbation out of its range: refused where parsed, not an error in every run.
    ["batch", "in.motion", "--no-cache", "--perturb", "mass=-1:0"],
    ["batch", "in.motion", "--no-cache", "--perturb", "speed=0:0"],
    ["batch", "in.motion", "--no-cache", "--perturb", "start-noise=-1:1"],
]

# A motion that plays for 23 days (100 million controller steps): what holds its stream whole,
# play and convert to a robot (they would compute for days) refuse it in one line; what reads
# it a chunk at a time (or at its pose times) finishes. Run under a 3 GiB address space limit
# (a step too many held would need tens of GB).
DAYS = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,P1,0,0\n40,P2,1.5,0\n2000000000,P3,0,0.1\n"
LONG_REFUSED = [
    ["play", "days.motion", "--headless"],
    ["resample", "days.motion", "--step", "20", "-o", "X"],
    ["convert", "days.motion", "X", "--to", "rosbag"],  # (naoqi: its robot check stops first)
]
LONG_FINISHED = [
    ["validate", "days.motion", "--robot", "nao"],  # MT115 and MT209 at the Nao's 20 ms
    ["validate", "days.motion"],  # at the steps next to its pose times: as fast as 3 lines
    ["diff", "days.motion", "days.motion"],  # at the steps next to its pose times
    ["diff", "days.motion", "days.motion", "--plot", "X"],  # the steps that shape the lines
    ["plot", "days.motion", "-o", "X"],  # a chunk of steps at a time: 10 s, 80 MiB
]
_LONG_LIMIT = 3 << 30

# Joint names matplotlib cannot draw as they are: bytes that are not UTF-8 (kept as surrogates),
# '$' signs (mathtext). Drawn escaped, as typed.
ODD_NAMES = [b"Bad\xff\xfeName", b"a$\\frac$", b"x$y"]
DRAWN = [["plot", "odd.motion", "-o", "X"], ["diff", "odd.motion", "odd2.motion", "--plot", "X"]]

# Two outputs on one path: refused before anything runs.
SHARED = [
    ["play", "in.motion", "--headless", "--json", "X", "--rrd", "X"],
    ["play", "in.motion", "--headless", "--rrd", "X", "--bag", "./X"],
    ["batch", "in.motion", "--json", "X", "--markdown", "X"],
    ["batch", "in.motion", "--json", "-", "--junit", "-"],
    ["batch", "in.motion", "--no-cache", "--rrd-dir", "X", "--json", "X/in.nao.0.rrd"],
    ["robots", "export", "ur5e", "--mjcf", "X", "--urdf", "./X"],
]

# Commands whose stdout goes to a full disk.
STDOUT = [
    ["validate", "in.motion"],
    ["sample", "in.motion"],
    ["codes"],
    ["info", "in.motion"],
    ["mirror", "in.motion", "-o", "-"],
    ["convert", "in.motion", "-", "--to", "csv"],
    ["convert", "in.motion", "-", "--to", "ros-trajectory"],
    ["convert", "in.motion", "-", "--to", "rosbag"],
    ["robots"],
]


@dataclass
class Tally:
    cases: int = 0
    failures: list[str] = field(default_factory=list)
    lock: threading.Lock = field(default_factory=threading.Lock)

    def record(self, name: str, problem: str | None) -> None:
        with self.lock:
            self.cases += 1
            if problem:
                self.failures.append(f"{name}: {problem}")
                print(f"FAIL {name}: {problem}", flush=True)


def _scratch() -> Path:
    here = Path(tempfile.mkdtemp(prefix="motiontool-hostile-"))
    (here / "in.motion").write_bytes(MOTION)
    (here / "other.motion").write_bytes(MOTION)
    return here


def _run(
    here: Path,
    line: list[str],
    *,
    stdout: int | None = subprocess.PIPE,
    memory: int | None = None,
) -> subprocess.CompletedProcess[bytes]:
    env = {**os.environ, "XDG_CACHE_HOME": str(here / "cache")}

    def limit() -> None:  # in the child, before it runs: its address space, bytes
        if memory is not None:
            resource.setrlimit(resource.RLIMIT_AS, (memory, memory))

    return subprocess.run(
        [SCRIPT, *line],
        cwd=here,
        stdout=stdout,
        stderr=subprocess.PIPE,
        env=env,
        timeout=300,
        check=False,
        preexec_fn=limit,
    )


def _traceback(err: bytes) -> str | None:
    return "traceback on stderr" if b"Traceback (most recent call last)" in err else None


def _mknod(path: Path, minor: int) -> bool:
    try:
        os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, minor))
    except PermissionError:
        return False
    return True


def _same_special(path: Path, kind: Callable[[int], bool], rdev: int | None = None) -> str | None:
    st = path.lstat()
    if not kind(st.st_mode) or (rdev is not None and st.st_rdev != rdev):
        return f"{path.name} was replaced (mode {stat.filemode(st.st_mode)})"
    return None


def case_device(line: list[str], minor: int, tally: Tally) -> None:
    here = _scratch()
    try:
        node = here / "dev"
        if not _mknod(node, minor):
            return
        done = _run(here, [a if a != "OUT" else "dev" for a in line])
        problem = _traceback(done.stderr) or _same_special(node, stat.S_ISCHR, os.makedev(1, minor))
        beside = sorted(p.name for p in here.iterdir() if p.name.startswith("dev") and p != node)
        if not problem and beside:  # a companion (naoqi's _send.py) goes beside files only
            problem = f"wrote {beside} beside the device"
        if not problem and minor == 7 and done.returncode != 2:
            problem = f"a full disk exited {done.returncode}, not 2"
        if not problem and minor == 3 and done.returncode not in (0, 1):
            problem = f"exit {done.returncode}: {done.stderr.decode(errors='replace')[-200:]}"
        tally.record(f"{' '.join(line)} > {'null' if minor == 3 else 'full'} node", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_fifo(line: list[str], tally: Tally) -> None:
    here = _scratch()
    try:
        fifo = here / "fifo"
        os.mkfifo(fifo)
        got: list[bytes] = []
        reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
        reader.start()
        done = _run(here, [a if a != "OUT" else "fifo" for a in line])
        reader.join(timeout=60)
        problem = _traceback(done.stderr) or _same_special(fifo, stat.S_ISFIFO)
        if not problem and not (got and got[0]):
            problem = "the FIFO's reader got nothing"
        tally.record(f"{' '.join(line)} > fifo", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_symlink(line: list[str], tally: Tally) -> None:
    here = _scratch()
    try:
        (here / "real").write_bytes(b"stale")
        (here / "link").symlink_to("real")
        done = _run(here, [a if a != "OUT" else "link" for a in line])
        problem = _traceback(done.stderr)
        if not problem and not (here / "link").is_symlink():
            problem = "the symlink was replaced by a regular file"
        if not problem and (here / "real").read_bytes() == b"stale":
            problem = "the link's target was left stale"
        tally.record(f"{' '.join(line)} > symlink", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_refused(line: list[str], tally: Tally, memory: int | None = None) -> None:
    here = _scratch()
    try:
        (here / "days.motion").write_bytes(DAYS)
        done = _run(here, line, memory=memory)
        err = done.stderr.decode(errors="replace")
        problem = _traceback(done.stderr)
        if not problem and (done.returncode != 2 or not err.startswith("motiontool: error: ")):
            problem = f"exit {done.returncode}, stderr {err[-200:]!r}"
        if not problem and err.count("\n") != 1:
            problem = f"{err.count(chr(10))} lines on stderr, not 1"
        if not problem and (here / "X").exists():
            problem = "an output was written"
        tally.record(" ".join(line), problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_empty_path(line: list[str], tally: Tally) -> None:
    """OUT = '' (pathlib's '.'): one line, exit 2, nothing written."""
    here = _scratch()
    try:
        done = _run(here, [a if a != "OUT" else "" for a in line])
        err = done.stderr.decode(errors="replace")
        problem = _traceback(done.stderr)
        if not problem and (done.returncode != 2 or err.count("\n") != 1):
            problem = f"exit {done.returncode}, stderr {err[-200:]!r}"
        left = sorted(p.name for p in here.iterdir()) if not problem else []
        if not problem and set(left) - {"cache", "in.motion", "other.motion"}:
            problem = f"wrote {left}"
        tally.record(f"{' '.join(line)} (OUT '')", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_drawn(line: list[str], name: bytes, tally: Tally) -> None:
    here = _scratch()
    try:
        for file, end in (("odd.motion", b"0.3"), ("odd2.motion", b"0.4")):
            (here / file).write_bytes(
                b"#WEBOTS_MOTION,V1.0,HeadYaw,%s\n0,P1,0,0\n1000,P2,0.5,%s\n" % (name, end)
            )
        done = _run(here, line)
        problem = _traceback(done.stderr)
        if not problem and (done.returncode not in (0, 1) or not (here / "X").is_file()):
            problem = f"exit {done.returncode}: {done.stderr.decode(errors='replace')[-200:]!r}"
        tally.record(f"{' '.join(line)} of joint {name!r}", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_full_folder(tally: Tally) -> None:
    """``batch --rrd-dir`` on a full disk (a 64 KiB tmpfs, filled): exit 2, one line, no
    report, no temporary file left. Needs root (mount); left out otherwise."""
    here = _scratch()
    full = here / "full"
    full.mkdir()
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(full)],
        capture_output=True,
        check=False,
    )
    if mounted.returncode != 0:
        shutil.rmtree(here, ignore_errors=True)
        return
    try:
        with contextlib.suppress(OSError):  # ENOSPC once the 64 KiB are taken
            (full / "filler").write_bytes(b"\0" * (1 << 20))
        line = ["batch", "in.motion", "--no-cache", "--rrd-dir", "full/rrd", "--json", "r.json"]
        done = _run(here, line)
        err = done.stderr.decode(errors="replace")
        problem = _traceback(done.stderr)
        if not problem and (done.returncode != 2 or err.count("\n") != 1):
            problem = f"exit {done.returncode}, stderr {err[-200:]!r}"
        if not problem and (here / "r.json").exists():
            problem = "the report was written"
        left = sorted(p.name for p in full.rglob("*") if p.name not in ("filler", "rrd"))
        if not problem and left:
            problem = f"left {left} on the full disk"
        tally.record(" ".join(line) + " on a full disk", problem)
    finally:
        subprocess.run(["umount", str(full)], check=False)
        shutil.rmtree(here, ignore_errors=True)


def case_long_finished(line: list[str], tally: Tally) -> None:
    here = _scratch()
    try:
        (here / "days.motion").write_bytes(DAYS)
        done = _run(here, line, memory=_LONG_LIMIT)
        problem = _traceback(done.stderr)
        if not problem and done.returncode not in (0, 1):
            problem = f"exit {done.returncode}: {done.stderr.decode(errors='replace')[-200:]!r}"
        tally.record(f"{' '.join(line)} in 3 GiB", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_stdout_full(line: list[str], tally: Tally) -> None:
    here = _scratch()
    try:
        if not _mknod(here / "full", 7):
            return
        with (here / "full").open("wb") as full:
            done = _run(here, line, stdout=full.fileno())
        problem = _traceback(done.stderr)
        if not problem and done.returncode != 2:
            problem = f"stdout on a full disk exited {done.returncode}, not 2"
        tally.record(f"{' '.join(line)} with stdout on a full disk", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_broken_pipe(tally: Tally) -> None:
    here = _scratch()
    try:
        rows = b"".join(b"%d,P,0.1,0.2\n" % t for t in range(40, 200000, 40))
        (here / "long.motion").write_bytes(MOTION.splitlines(keepends=True)[0] + rows)
        proc = subprocess.Popen(
            [SCRIPT, "sample", "long.motion", "-t", "1"],
            cwd=here,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        assert proc.stdout is not None and proc.stderr is not None
        proc.stdout.readline()
        proc.stdout.close()
        with proc.stderr:
            err = proc.stderr.read()
        code = proc.wait(timeout=120)
        problem = _traceback(err) or (None if code == 141 else f"exit {code}, not 141")
        tally.record("sample | head -1", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_ctrl_c(tally: Tally) -> None:
    here = _scratch()
    try:
        cache = here / "cache-dir"
        line = ["batch", "in.motion", "--samples", "400", "--perturb", "friction=0.8:1.2"]
        # As from a terminal: SIGINT at its default. A shell starts a background job with
        # SIGINT ignored (`.ci/run &`, nohup), the ignore is inherited through exec, and
        # Python then installs no handler: the batch would ignore the Ctrl-C and end with 0.
        default_sigint = (
            "import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); "
            "os.execv(sys.argv[1], sys.argv[1:])"
        )
        proc = subprocess.Popen(
            [sys.executable, "-c", default_sigint, SCRIPT, *line, "--cache-dir", str(cache)],
            cwd=here,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            start_new_session=True,
        )
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and len(list(cache.rglob("*.json"))) < 2:
            time.sleep(0.2)
        os.killpg(proc.pid, signal.SIGINT)
        _, err = proc.communicate(timeout=60)
        problem = _traceback(err)
        if not problem and proc.returncode != 130:
            problem = f"exit {proc.returncode}, not 130"
        if not problem and err != b"motiontool: error: interrupted\n":
            problem = f"stderr {err[-200:]!r}"
        tally.record("batch, Ctrl-C", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


# A standard stream the shell closed (>&-, 2>&-, <&-): (redirect, command line, exit code, what
# stderr must be; None: anything without a traceback).
CLOSED = [
    (">&-", ["-V"], 2, b"motiontool: error: cannot write to standard output: it is closed\n"),
    (">&-", ["codes"], 2, b"motiontool: error: cannot write to standard output: it is closed\n"),
    (">&-", ["validate", "in.motion"], 2, None),
    (">&-", ["sample", "in.motion", "-o", "X"], 0, None),  # nothing written to stdout: fine
    ("2>&-", ["validate", "in.motion"], 0, None),
    ("2>&-", ["validate", "missing.motion"], 2, None),
    ("<&-", ["validate", "-"], 2, None),
]

# SIGTERM or SIGHUP while an output is being written: (signal, command line, what appears in
# the scratch folder (or its TMPDIR) once the output is under way).
BIG_ROWS = b"".join(
    b"%d,P,%.3f,%.3f\n" % (t, t % 1000 / 1000, t % 700 / 1000) for t in range(0, 600000, 40)
)
SIGNALLED = [
    (signal.SIGTERM, ["resample", "big.motion", "--step", "1", "-o", "X"], ".X.*.tmp"),
    (signal.SIGHUP, ["resample", "big.motion", "--step", "1", "-o", "X"], ".X.*.tmp"),
    (signal.SIGTERM, ["play", "long.motion", "--headless", "--rrd", "X"], "tmp/motiontool-*"),
    (
        signal.SIGTERM,
        [
            "batch",
            "long.motion",
            "--samples",
            "40",
            "--perturb",
            "friction=0.8:1.2",
            "--json",
            "X",
            "--cache-dir",
            "C",
        ],
        "C/*/*.json",
    ),
]


def _script_with(redirect: str, here: Path, line: list[str]) -> subprocess.CompletedProcess[bytes]:
    env = {**os.environ, "XDG_CACHE_HOME": str(here / "cache")}
    return subprocess.run(
        ["sh", "-c", f'exec "$@" {redirect}', "sh", SCRIPT, *line],
        cwd=here,
        capture_output=True,
        env=env,
        timeout=300,
        check=False,
    )


def case_closed(redirect: str, line: list[str], code: int, err: bytes | None, tally: Tally) -> None:
    """A closed standard stream is one line and an exit code, no traceback."""
    here = _scratch()
    try:
        done = _script_with(redirect, here, line)
        problem = _traceback(done.stderr)
        if not problem and done.returncode != code:
            problem = f"exit {done.returncode}, not {code}: {done.stderr[-200:]!r}"
        if not problem and err is not None and done.stderr != err:
            problem = f"stderr {done.stderr[-200:]!r}"
        tally.record(f"{' '.join(line)} {redirect}", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_server_exit(tally: Tally) -> None:
    """The LSP server exits 0 after a clean shutdown and exit."""
    here = _scratch()
    try:
        talk = b""
        for message in (
            b'{"jsonrpc":"2.0","id":1,"method":"initialize","params":{"capabilities":{}}}',
            b'{"jsonrpc":"2.0","method":"initialized","params":{}}',
            b'{"jsonrpc":"2.0","id":2,"method":"shutdown"}',
            b'{"jsonrpc":"2.0","method":"exit"}',
        ):
            talk += b"Content-Length: %d\r\n\r\n" % len(message) + message
        done = subprocess.run(
            [SCRIPT, "server"], input=talk, capture_output=True, cwd=here, timeout=120, check=False
        )
        missing = b"needs" in done.stderr and b"lsp" in done.stderr  # the extra not installed
        problem = None if missing else _traceback(done.stderr)
        if not problem and not missing and (done.returncode, done.stderr) != (0, b""):
            problem = f"exit {done.returncode}: {done.stderr[-200:]!r}"
        tally.record("server: shutdown, exit", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def case_signalled(signum: int, line: list[str], under_way: str, tally: Tally) -> None:
    """SIGTERM or SIGHUP mid-write: exit 128 + N with one line, no temporary
    file beside the output or in TMPDIR, no worker left running, no output."""
    here = _scratch()
    try:
        head = MOTION.splitlines(keepends=True)[0]
        (here / "big.motion").write_bytes(head + BIG_ROWS)
        rows = b"".join(b"%d,P,%.3f,0\n" % (t, t % 1000 / 2000) for t in range(0, 120000, 400))
        (here / "long.motion").write_bytes(head + rows)
        (here / "tmp").mkdir()
        env = {**os.environ, "XDG_CACHE_HOME": str(here / "cache"), "TMPDIR": str(here / "tmp")}
        proc = subprocess.Popen(
            [SCRIPT, *line],
            cwd=here,
            env=env,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            start_new_session=True,
        )
        deadline = time.monotonic() + 120
        while (
            not list(here.glob(under_way)) and proc.poll() is None and time.monotonic() < deadline
        ):
            time.sleep(0.01)
        workers = _children(proc.pid)
        proc.send_signal(signum)
        try:
            _, err = proc.communicate(timeout=60)
        finally:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
        name = {signal.SIGTERM: b"terminated", signal.SIGHUP: b"hangup"}[signum]
        problem = _traceback(err)
        said = b"motiontool: error: " + name + b"\n"
        if not problem and (proc.returncode, err) != (exit_codes.BY_SIGNAL[signum], said):
            problem = f"exit {proc.returncode}, stderr {err[-200:]!r}"
        debris = [str(p.relative_to(here)) for p in here.rglob("*") if p.name.endswith(".tmp")]
        debris += [str(p.relative_to(here)) for p in (here / "tmp").iterdir()]
        if not problem and debris:
            problem = f"left behind: {debris}"
        if not problem and (here / "X").exists():
            problem = "the output was written"
        if not problem and [w for w in workers if _running(w)]:
            problem = "a worker is still running"
        tally.record(f"{' '.join(line)}, {signal.Signals(signum).name}", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def _children(pid: int) -> list[int]:
    with contextlib.suppress(OSError):
        return [int(p) for p in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    return []


def _running(pid: int) -> bool:
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            return False
        if state == "Z":
            return False
        time.sleep(0.05)
    return True


def case_walk(tally: Tally) -> None:
    """A folder search names what it cannot read (a dangling .motion link, a
    link loop; a folder nobody may list, where the script does not run as root) and exits 2."""
    here = _scratch()
    try:
        (here / "m" / "ok").mkdir(parents=True)
        (here / "m" / "ok" / "a.motion").write_bytes(MOTION)
        (here / "m" / "gone.motion").symlink_to("nowhere.motion")
        (here / "m" / "loop.motion").symlink_to("loop.motion")
        expected = [b"'m/gone.motion': No such file", b"'m/loop.motion': Too many levels"]
        if os.geteuid() != 0:
            (here / "m" / "locked").mkdir(mode=0)
            expected.append(b"'m/locked': Permission denied")
        for line in (["validate", "m"], ["batch", "m", "--no-cache"], ["expect", "--infer", "m"]):
            done = _run(here, line)
            problem = _traceback(done.stderr)
            if not problem and (done.returncode != 2 or done.stderr.count(b"\n") != 1):
                problem = f"exit {done.returncode}: {done.stderr[-300:]!r}"
            if not problem and not all(e in done.stderr for e in expected):
                problem = f"not every entry named: {done.stderr[-300:]!r}"
            tally.record(f"{' '.join(line)} over a dangling link and a loop", problem)
    finally:
        with contextlib.suppress(OSError):
            (here / "m" / "locked").chmod(0o755)
        shutil.rmtree(here, ignore_errors=True)


# Text from a file or an option that a message echoes: (file's bytes or None, command line).
ECHOED = [
    (b"#WEBOTS_MOTION,V1.0,Head\x1b[31mYaw\n0,P\x1b]0;t\x07,0x\x1b[2J\n", ["validate", "e.motion"]),
    (
        b"#WEBOTS_MOTION,V1.0,Head\x1b[31mYaw\n0,P\x1b]0;t\x07,0x\x1b[2J\n",
        ["validate", "e.motion", "--format", "github"],
    ),
    (
        b"#WEBOTS_MOTION,V1.0," + b"H" * 4000 + b"\n0,P,0\n",
        ["validate", "e.motion", "--robot", "nao"],
    ),
    (b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P," + b"1" * 1000000 + b"\n", ["validate", "e.motion"]),
    (b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,P," + b"1" * 1000000 + b"\n", ["sample", "e.motion"]),
    (None, ["batch", "in.motion", "--expect", "a" * 5000]),
]


def case_echoed(data: bytes | None, line: list[str], tally: Tally) -> None:
    """What a message echoes is cut (no line of 1,000 characters) and its
    control characters escaped (no ESC, BEL reaches the terminal)."""
    here = _scratch()
    try:
        if data is not None:
            (here / "e.motion").write_bytes(data)
        done = _run(here, line)
        out = done.stdout + done.stderr
        problem = _traceback(done.stderr)
        longest = max((len(x) for x in out.splitlines()), default=0)
        if not problem and longest > 1000:
            problem = f"a line of {longest} characters"
        if not problem and any(c < 0x20 and c != 0x0A for c in out):
            problem = "a control character reached the terminal"
        tally.record(f"{' '.join(a[:20] for a in line)}: echoed text", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


# A 3-line file whose last pose is past 2^31 ms took 10 s to validate; what
# validation costs must not follow how long the motion plays (0.2 s here; 3 s leaves room for a
# loaded machine, where a run per controller step would take seconds).
PAST = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,P1,0,0\n40,P2,1.5,0\n2200000000,P3,0,0.1\n"
QUICK = [["validate", "past.motion"], ["validate", "past.motion", "--robot", "nao"]]
_QUICK_S = 3.0


def case_quick(line: list[str], tally: Tally) -> None:
    here = _scratch()
    try:
        (here / "past.motion").write_bytes(PAST)
        t0 = time.monotonic()
        done = _run(here, line)
        wall = time.monotonic() - t0
        problem = _traceback(done.stderr)
        if not problem and done.returncode not in (0, 1):
            problem = f"exit {done.returncode}: {done.stderr[-200:]!r}"
        if not problem and wall > _QUICK_S:
            problem = f"{wall:.1f} s, over {_QUICK_S:g} s"
        tally.record(f"{' '.join(line)}: past 2^31 ms", problem)
    finally:
        shutil.rmtree(here, ignore_errors=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=2, help="cases run at once")
    args = parser.parse_args()
    tally = Tally()
    rooted = _mknod(Path(tempfile.mkdtemp()) / "probe", 3)
    cases: list[Callable[[], None]] = []
    for line in WRITERS:
        cases += [
            lambda line=line: case_fifo(line, tally),
            lambda line=line: case_symlink(line, tally),
            lambda line=line: case_empty_path(line, tally),
        ]
        if rooted:
            cases += [
                lambda line=line: case_device(line, 3, tally),
                lambda line=line: case_device(line, 7, tally),
            ]
    cases += [lambda line=line: case_refused(line, tally) for line in HUGE + SHARED]
    cases += [lambda line=line: case_refused(line, tally, _LONG_LIMIT) for line in LONG_REFUSED]
    cases += [lambda line=line: case_long_finished(line, tally) for line in LONG_FINISHED]
    cases += [
        lambda line=line, name=name: case_drawn(line, name, tally)
        for line in DRAWN
        for name in ODD_NAMES
    ]
    if rooted:
        cases += [lambda line=line: case_stdout_full(line, tally) for line in STDOUT]
        cases.append(lambda: case_full_folder(tally))
    cases += [lambda: case_broken_pipe(tally), lambda: case_ctrl_c(tally)]
    cases += [lambda c=c: case_closed(*c, tally) for c in CLOSED]
    cases += [lambda: case_server_exit(tally), lambda: case_walk(tally)]
    cases += [lambda c=c: case_signalled(*c, tally) for c in SIGNALLED]
    cases += [lambda c=c: case_echoed(*c, tally) for c in ECHOED]
    cases += [lambda line=line: case_quick(line, tally) for line in QUICK]
    t0 = time.monotonic()
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for future in [pool.submit(case) for case in cases]:
            future.result()
    wall = time.monotonic() - t0
    where = "" if rooted else " (not root: device-node cases left out)"
    print(
        f"hostile: {tally.cases} cases, {len(tally.failures)} failed "
        f"(tracebacks or replaced special files){where}; {wall:.0f} s"
    )
    return 1 if tally.failures else 0


if __name__ == "__main__":
    sys.exit(main())
