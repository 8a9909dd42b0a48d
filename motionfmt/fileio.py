"""Reading motion files (``-``: standard input) and writing them safely (temporary file, then
rename)."""

from __future__ import annotations

import contextlib
import errno
import os
import re
import signal
import stat
import sys
import threading
import weakref
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, BinaryIO

from motiontool.errors import MotionToolError, OutputError

if TYPE_CHECKING:
    import tempfile

__all__ = [
    "STDIN",
    "STDIN_NAME",
    "STDOUT",
    "STDOUT_NAME",
    "Inputs",
    "Sink",
    "atomic_write",
    "collect_motion_files",
    "is_folder",
    "is_stdin",
    "is_stdout",
    "open_output",
    "output_kind",
    "read_file",
    "source_name",
    "temporary_folder",
]

STDIN = "-"
"""The path that means standard input where a motion file is read."""

STDIN_NAME = "<stdin>"
"""How diagnostics and reports name standard input."""

# Standard input can be read only once; a command that reads '-' twice (play reads each file
# again, diff - -) gets the same bytes. Keyed by the stream, so a new stdin is read afresh.
_stdin_bytes: weakref.WeakKeyDictionary[object, bytes] = weakref.WeakKeyDictionary()


def is_stdin(path: str | Path) -> bool:
    """True for ``-``, the path that stands for standard input."""
    return str(path) == STDIN


def source_name(path: str | Path) -> str:
    """How diagnostics name ``path``: ``<stdin>`` for ``-``, else the path as given."""
    return STDIN_NAME if is_stdin(path) else str(path)


def _read_stdin() -> bytes:
    stream = sys.stdin
    if stream is None:
        raise MotionToolError(f"cannot read '{STDIN}' ({STDIN_NAME}): there is no standard input")
    source: object = getattr(stream, "buffer", stream)
    cached = _stdin_bytes.get(source)
    if cached is not None:
        return cached
    try:
        raw = source.read()  # type: ignore[attr-defined]
    except OSError as exc:
        raise MotionToolError(f"cannot read {STDIN_NAME}: {exc.strerror or exc}") from exc
    data = raw if isinstance(raw, bytes) else str(raw).encode("utf-8", "surrogateescape")
    with contextlib.suppress(TypeError):  # a stream that takes no weak reference: not cached
        _stdin_bytes[source] = data
    return data


def _rereadable(path: str | Path) -> bool:
    """Whether ``path`` can be read again later for the same bytes: a regular file this process
    may read (standard input, a pipe or a device cannot)."""
    if is_stdin(path):
        return False
    try:
        return stat.S_ISREG(os.stat(path).st_mode) and os.access(path, os.R_OK)
    except OSError:
        return False


class Inputs:
    """Input files read as often as a command needs them, not held: standard input, a pipe
    (``<(...)``) or a device, which cannot be read again, are read here once and held, and so
    is a file this process may not read (read now, its error comes before any output).

    Attributes:
        paths: the files, in order.
        names: how reports name them (:func:`source_name`).
        sizes: each one's size, bytes (of the file on disk, or of the bytes held).
    """

    def __init__(self, paths: Sequence[Path]) -> None:
        self.paths = list(paths)
        self.names = [source_name(p) for p in self.paths]
        self._held = {i: read_file(p) for i, p in enumerate(self.paths) if not _rereadable(p)}
        self.sizes = [
            len(self._held[i]) if i in self._held else os.stat(p).st_size
            for i, p in enumerate(self.paths)
        ]

    def read(self, i: int) -> bytes:
        """The bytes of the ``i``-th file (read again, or held)."""
        return self._held[i] if i in self._held else read_file(self.paths[i])


def read_file(path: str | Path) -> bytes:
    """The bytes of ``path`` (``-``: standard input, read once).

    Raises:
        MotionToolError: one line, ``cannot read 'PATH': REASON``, whatever the reason (missing,
            a directory, permission denied, a parent that is not a directory).
    """
    if is_stdin(path):
        return _read_stdin()
    try:
        return Path(path).read_bytes()
    except IsADirectoryError as exc:
        raise MotionToolError(
            f"cannot read '{path}': {exc.strerror}, expected a .motion file"
        ) from exc
    except OSError as exc:
        raise MotionToolError(f"cannot read '{path}': {exc.strerror or exc}") from exc


STDOUT = "-"
"""The path that means standard output where a command writes a file."""

# Paths that name a file descriptor the process already has: written through that descriptor
# (its mode, append or not, and its position are the caller's), never opened or replaced.
_FD_PATH = re.compile(r"/(?:dev/fd|proc/self/fd|proc/thread-self/fd)/(\d+)")
_STD_PATHS = {"/dev/stdout": 1, "/dev/stderr": 2}


def is_stdout(path: str | Path | None) -> bool:
    """True for ``-``, the output path that stands for standard output."""
    return path is not None and str(path) == STDOUT


def _descriptor(path: str | Path) -> int | None:
    """The file descriptor that ``path`` names (``/dev/fd/N``, ``/proc/self/fd/N``,
    ``/dev/stdout``, ``/dev/stderr``), or None for any other path."""
    text = os.path.normpath(str(path))
    if text in _STD_PATHS:
        return _STD_PATHS[text]
    match = _FD_PATH.fullmatch(text)
    return int(match.group(1)) if match else None


def output_kind(path: str | Path) -> str:
    """How :func:`open_output` writes ``path``: ``stdout`` (``-``), ``descriptor`` (a
    ``/dev/fd/N`` path), ``special`` (an existing character or block device, FIFO or socket,
    through symlinks: written straight through) or ``file`` (a regular file or a new path:
    written atomically, through symlinks to their target)."""
    if is_stdout(path):
        return "stdout"
    if _descriptor(path) is not None:
        return "descriptor"
    try:
        mode = os.stat(path).st_mode  # follows symlinks: what the path points at
    except OSError:
        return "file"
    return "file" if stat.S_ISREG(mode) or stat.S_ISDIR(mode) else "special"


def _cannot_write(path: str | Path, exc: OSError) -> OutputError:
    return OutputError(f"cannot write '{path}': {exc.strerror or exc}")


@contextlib.contextmanager
def open_output(path: str | Path) -> Iterator[Sink]:
    """A binary stream that writes ``path`` without harming what the path names.

    - ``-``: standard output (left open);
    - ``/dev/fd/N``, ``/dev/stdout``, ``/dev/stderr``: that descriptor, as the shell opened it
      (appending where it appends);
    - a character or block device, a FIFO or a socket (through symlinks too): written straight
      through, never replaced (a FIFO's reader gets the data, ``/dev/full`` reports a full
      disk);
    - anything else (a regular file, a new path, a symlink to either): all or nothing, a
      temporary file beside the real file, then a rename over it; a symlink stays a symlink and
      its target gets the data; missing parent folders are created; an existing file keeps its
      permission bits (and its owner, where the process may set it).

    The data is committed when the ``with`` block ends without an exception; on an exception
    a temporary file is removed and the target is left as it was.

    Raises:
        OutputError: ``cannot write 'PATH': REASON``, whatever the reason.
    """
    kind = output_kind(path)
    if kind == "file":
        with _atomic(path) as stream:
            yield Sink(stream)
        return
    if kind == "stdout":
        with _stdout() as stream:
            yield Sink(stream)
        return
    try:
        fd = _descriptor(path)
        if fd is not None:
            if fd in (1, 2):
                (sys.stdout if fd == 1 else sys.stderr).flush()
            stream = os.fdopen(os.dup(fd), "wb")
        else:
            stream = open(path, "wb")  # noqa: SIM115 - closed below, errors mapped
    except OSError as exc:
        raise _cannot_write(path, exc) from exc
    try:
        with stream:
            yield Sink(stream)
            stream.flush()
    except OSError as exc:
        raise _cannot_write(path, exc) from exc


class Sink:
    """What :func:`open_output` yields: ``write`` writes all of ``data`` or raises.

    A buffered stream may return a short count instead of raising, when a pipe's reader goes
    away in the middle of a large write, or a disk fills up: the data would be cut without a
    word. ``write`` goes on until everything is written, so the next attempt raises the error.
    """

    __slots__ = ("_stream",)

    def __init__(self, stream: BinaryIO) -> None:
        self._stream = stream

    def write(self, data: bytes | bytearray | memoryview) -> int:
        """Write all of ``data``; the number of bytes (all of them)."""
        view = memoryview(data).cast("B")
        total = len(view)
        while view:
            n = self._stream.write(view)
            if n is None or n <= 0:
                raise OSError(errno.EIO, os.strerror(errno.EIO))
            view = view[n:]
        return total

    def flush(self) -> None:
        self._stream.flush()


STDOUT_NAME = "standard output"
"""How errors name standard output."""


@contextlib.contextmanager
def _stdout() -> Iterator[BinaryIO]:
    """``sys.stdout``'s bytes, flushed at the end and never closed; a write that fails (a full
    disk) raises ``cannot write to standard output: REASON``; a closed pipe
    (:class:`BrokenPipeError`) is left to the entry point, which ends quietly."""
    try:
        sys.stdout.flush()
        buffer: BinaryIO = sys.stdout.buffer
        yield buffer
        buffer.flush()
    except BrokenPipeError:
        raise
    except OSError as exc:
        raise OutputError(f"cannot write to {STDOUT_NAME}: {exc.strerror or exc}") from exc


@contextlib.contextmanager
def _atomic(path: str | Path) -> Iterator[BinaryIO]:
    target = Path(os.path.realpath(path))  # a symlink's target gets the data
    try:
        st: os.stat_result | None = target.stat()
    except FileNotFoundError:
        st = None
    except OSError as exc:
        raise _cannot_write(path, exc) from exc
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise OutputError(f"cannot write '{path}': Is a directory")
    if st is not None:
        mode = st.st_mode & 0o7777
    else:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    import tempfile  # only to write a file

    tmp = ""
    try:
        with _signals_held():  # the temporary file and its removal below: one step
            target.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
        with os.fdopen(fd, "wb") as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, mode)
        if st is not None and (st.st_uid, st.st_gid) != (os.geteuid(), os.getegid()):
            with contextlib.suppress(OSError):  # only root may give a file away
                os.chown(tmp, st.st_uid, st.st_gid)
        os.replace(tmp, target)
    except OSError as exc:
        if tmp:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise _cannot_write(path, exc) from exc
    except BaseException:
        if tmp:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise


_HELD = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGALRM)
"""The signals that end a command (SIGALRM: the CLI raises a swallowed SIGTERM again by it)."""


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """The signals of :data:`_HELD` held back in the block, sent again once it ends: a file made
    in it and the ``try`` that removes it are one step (a signal between them would leave the
    file). Their handlers run in the main thread only, so only it holds them (another
    thread's block is not cut by a signal)."""
    if threading.current_thread() is not threading.main_thread() or any(
        signal.getsignal(s) is None
        for s in _HELD  # a handler set outside Python: kept
    ):
        yield
        return
    came: list[int] = []
    previous = {s: signal.signal(s, lambda signum, frame: came.append(signum)) for s in _HELD}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        for signum in came[:1]:  # handled now, by its own handler
            signal.raise_signal(signum)


def temporary_folder(prefix: str) -> tempfile.TemporaryDirectory[str]:
    """A temporary folder (``tempfile.TemporaryDirectory``) made with its removal armed in one
    step: a signal that comes while it is made is handled once the object that removes it
    exists (:func:`_signals_held`), so SIGTERM never leaves the folder behind."""
    import tempfile

    folder = None
    try:
        with _signals_held():
            folder = tempfile.TemporaryDirectory(prefix=prefix)
    except BaseException:  # the signal held while it was made: the folder goes with it
        if folder is not None:
            folder.cleanup()
        raise
    return folder


def atomic_write(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` as :func:`open_output` does: regular files all or nothing
    (a temporary file, then a rename), devices, FIFOs and descriptors straight through, ``-``
    to standard output.

    Raises:
        OutputError: ``cannot write 'PATH': REASON``.
    """
    with open_output(path) as stream:
        stream.write(data)


def is_folder(path: str | Path) -> bool:
    """Whether ``path`` is a folder (through symlinks); False where it cannot be told (a
    parent that may not be searched): reading it then says why."""
    try:
        return stat.S_ISDIR(os.stat(path).st_mode)
    except (OSError, ValueError):
        return False


_SHOWN_PROBLEMS = 5
"""At most this many entries a folder search could not read are named in its error line."""


def _search(
    folder: Path, found: list[Path], problems: list[tuple[Path, str]], skip_hidden: bool
) -> None:
    """Add the ``*.motion`` files below ``folder`` to ``found`` (regular files, through symlinks;
    symlinked folders are not entered; with ``skip_hidden``, nor folders whose name starts with
    a dot), and to ``problems`` each entry that cannot be read, with the reason: a folder that
    may not be listed, a ``.motion`` link to nothing or to itself."""
    try:
        with os.scandir(folder) as it:
            entries = sorted(it, key=lambda entry: entry.name)
    except OSError as exc:
        problems.append((folder, f"'{folder}': {exc.strerror or exc}"))
        return
    for entry in entries:
        path = folder / entry.name
        try:
            inside = entry.is_dir(follow_symlinks=False)
        except OSError:
            inside = False
        if inside:
            if not (skip_hidden and entry.name.startswith(".")):
                _search(path, found, problems, skip_hidden)
        elif entry.name.endswith(".motion"):
            try:
                if stat.S_ISREG(os.stat(path).st_mode):
                    found.append(path)
            except OSError as exc:
                reason = exc.strerror or str(exc)
                with contextlib.suppress(OSError):
                    if exc.errno != errno.ELOOP and entry.is_symlink():
                        reason += f" (a symbolic link to '{os.readlink(path)}')"
                problems.append((path, f"'{path}': {reason}"))


def collect_motion_files(
    paths: Iterable[str | Path],
    *,
    skip_hidden: bool = False,
    left_out: Callable[[list[Path]], set[Path]] | None = None,
) -> list[Path]:
    """Expand directories to the ``*.motion`` files below them (sorted, recursive; with
    ``skip_hidden``, folders whose name starts with a dot below a named one are not searched).

    Files named explicitly are kept whatever their extension; ``-`` (standard input) is kept
    as is. Raises :class:`MotionToolError` for a path that cannot be read (``cannot read
    'PATH': REASON``, as :func:`read_file`), a directory with no motion file, or a search that
    met entries it cannot read, as ruff's E902 (``cannot read 3 entries under 'm': 'm/locked':
    Permission denied; 'm/gone.motion': No such file or directory (a symbolic link to ...)``:
    a folder that may not be listed, a dangling ``.motion`` link, a link loop), but for those
    ``left_out`` says the search leaves out (of the entries it is given: excluded, ignored).
    """
    files: list[Path] = []
    for raw in paths:
        p = Path(raw)
        if is_stdin(raw):
            files.append(p)
            continue
        try:
            mode = p.stat().st_mode
        except OSError as exc:
            raise MotionToolError(f"cannot read '{raw}': {exc.strerror or exc}") from exc
        if stat.S_ISDIR(mode):
            found: list[Path] = []
            met: list[tuple[Path, str]] = []
            try:  # the folder itself: one reason
                os.scandir(p).close()
            except OSError as exc:
                raise MotionToolError(f"cannot read '{raw}': {exc.strerror or exc}") from exc
            _search(p, found, met, skip_hidden)
            gone = left_out([q for q, _ in met]) if left_out is not None and met else set()
            problems = [why for q, why in met if q not in gone]
            if problems:
                more = len(problems) - _SHOWN_PROBLEMS
                raise MotionToolError(
                    f"cannot read {len(problems)} {'entry' if len(problems) == 1 else 'entries'}"
                    f" under '{raw}': {'; '.join(problems[:_SHOWN_PROBLEMS])}"
                    + (f"; and {more} more" if more > 0 else "")
                )
            found.sort()
            if not found:
                raise MotionToolError(f"no .motion file under '{raw}'")
            files.extend(found)
        else:
            files.append(p)
    return files
