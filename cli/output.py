"""Writing a command's output to stdout or to a file (atomically), never over an input."""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import AnyStr

import typer

from motiontool.cli.text import plural
from motiontool.errors import MotionToolError
from motiontool.motionfmt.fileio import (
    STDOUT,
    atomic_write,
    is_stdin,
    is_stdout,
    open_output,
    output_kind,
)
from motiontool.motionfmt.units import MS_PER_S

__all__ = [
    "emit",
    "emit_bytes",
    "emit_files",
    "emit_pieces",
    "emit_stderr",
    "in_blocks",
    "piece_sink",
    "refuse_overwrite",
    "refuse_shared_outputs",
    "require_folder",
    "same_file",
    "say_wrote",
    "written_motion",
]


def same_file(a: Path, b: Path) -> bool:
    """True when ``a`` and ``b`` name one file: the same path, a symlink to it or a hard link
    (same device and inode); paths that do not both exist are compared resolved."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return a.resolve() == b.resolve()


def refuse_overwrite(
    output: Path | None,
    inputs: Iterable[Path],
    option: str,
    advice: str = "write to another file",
) -> None:
    """Refuse to write ``output`` where it is one of ``inputs`` (through a symlink or a hard
    link too): every command that writes a file calls this before it reads or writes anything.

    ``None`` and ``-`` (stdout) are never an input file; nor is an output that does not exist
    yet.

    Raises:
        MotionToolError: ``OPTION 'OUTPUT' is the input file ['INPUT']; ADVICE``.
    """
    if output is None or is_stdin(output) or not os.path.lexists(output):
        return
    for source in inputs:
        if is_stdin(source) or not same_file(output, source):
            continue
        named = "" if str(source) == str(output) else f" '{source}'"
        raise MotionToolError(f"{option} '{output}' is the input file{named}; {advice}")


def emit(text: str, output: Path | None) -> None:
    """Write ``text`` to ``output`` (temporary file, then rename) or to stdout.

    Names read from a file keep undecodable bytes as surrogates; they are written back as the
    original bytes.
    """
    emit_bytes(text.encode("utf-8", "surrogateescape"), output)


def emit_pieces(
    pieces: Iterable[str],
    output: Path | None,
    *,
    color: bool = False,
    before_writing: Callable[[], None] | None = None,
) -> None:
    """Write text made in pieces (a report that streams its findings) as they come, as
    :func:`piece_sink` writes them."""
    with piece_sink(output, color=color, before_writing=before_writing) as write:
        for piece in pieces:
            write(piece)


@contextlib.contextmanager
def piece_sink(
    output: Path | None,
    *,
    color: bool = False,
    before_writing: Callable[[], None] | None = None,
) -> Iterator[Callable[[str], None]]:
    """A ``write(piece)`` for text handed over in pieces as it is made (a report that streams
    its findings), written a block of about 64 KiB at a time, to ``output`` as :func:`emit`
    writes (a regular file is whole or untouched) or to stdout; ``color``: to a terminal
    through Click, which keeps the ANSI colours. ``before_writing`` is called once, before the
    first block is written (a progress display on the same terminal ends there)."""
    if color and output is None:
        blocks = _Blocks(lambda block: typer.echo(block, nl=False, color=True), before_writing)
        yield blocks.write
        blocks.close()
        return
    with open_output(STDOUT if output is None else output) as sink:
        blocks = _Blocks(lambda b: sink.write(b.encode("utf-8", "surrogateescape")), before_writing)
        yield blocks.write
        blocks.close()


class _Blocks:
    """Pieces of text joined into blocks of about ``size`` characters, each handed to
    ``put``; ``before`` is called once, before the first block (or at the end if none)."""

    def __init__(
        self, put: Callable[[str], object], before: Callable[[], None] | None, size: int = 1 << 16
    ) -> None:
        self.put, self.before, self.size = put, before, size
        self.held: list[str] = []
        self.n = 0

    def write(self, piece: str) -> None:
        self.held.append(piece)
        self.n += len(piece)
        if self.n >= self.size:
            self._flush()

    def close(self) -> None:
        self._flush()

    def _flush(self) -> None:
        if self.before is not None:
            self.before()
            self.before = None
        if self.held:
            self.put("".join(self.held))
            self.held, self.n = [], 0


def in_blocks(pieces: Iterable[AnyStr], size: int = 1 << 16) -> Iterator[AnyStr]:
    """``pieces`` (text or bytes) joined into blocks of about ``size`` characters or bytes:
    what is written at once."""
    held: list[AnyStr] = []
    n = 0
    for piece in pieces:
        held.append(piece)
        n += len(piece)
        if n >= size:
            yield piece[:0].join(held)
            held, n = [], 0
    if held:
        yield held[0][:0].join(held)


def emit_stderr(text: str) -> None:
    """Write ``text`` to stderr (a report whose stdout another output took), names' bytes kept."""
    sys.stderr.flush()
    sys.stderr.buffer.write(text.encode("utf-8", "surrogateescape"))
    sys.stderr.buffer.flush()


def say_wrote(output: Path | None, detail: str) -> None:
    """Say on stderr, in one line, that a command wrote the file ``output``:
    ``motiontool: wrote out/walk20.motion (339 poses, 6.76 s)`` (``detail`` in the parentheses:
    what the file holds, with units). Nothing for None or ``-``: that output is stdout itself.
    Every command that writes a file says it here, after the file is whole."""
    if output is None or is_stdout(output):
        return
    emit_stderr(f"motiontool: wrote {output} ({detail})\n")


def written_motion(poses: int, duration_ms: int) -> str:
    """The ``detail`` of :func:`say_wrote` for a motion file: ``339 poses, 6.76 s``."""
    return f"{plural(poses, 'pose')}, {duration_ms / MS_PER_S:g} s"


def emit_bytes(data: bytes, output: Path | None) -> None:
    """Write ``data`` to ``output`` as :func:`motiontool.motionfmt.fileio.open_output` does
    (a regular file atomically, a device, FIFO or ``/dev/fd/N`` straight through) or, for None
    or ``-``, to stdout."""
    atomic_write(STDOUT if output is None else output, data)


def emit_files(outputs: Sequence[tuple[Path | None, bytes]]) -> None:
    """Write several outputs as one, all or none: each as :func:`emit_bytes` writes it, every
    regular file to a temporary file first; a file is renamed into place only when every
    output after it is written (the last one first), and if a rename fails, the files renamed
    before it are removed. An interrupted or failed write leaves none of the regular files."""
    done: list[Path] = []
    try:
        _emit_nested(outputs, done)
    except BaseException:
        for path in done:
            with contextlib.suppress(OSError):
                os.unlink(os.path.realpath(path))
        raise


def _emit_nested(outputs: Sequence[tuple[Path | None, bytes]], done: list[Path]) -> None:
    (path, data), rest = outputs[0], outputs[1:]
    target = STDOUT if path is None else path
    with open_output(target) as sink:
        sink.write(data)
        if rest:
            _emit_nested(rest, done)
    if path is not None and output_kind(path) == "file":
        done.append(path)


def _one_output(a: Path, b: Path) -> bool:
    """True when writing ``a`` and then ``b`` would leave only one of them: the same regular
    file (a link to it too, or one new path) or standard output twice. Devices, FIFOs and
    ``/dev/fd/N`` take what they are given: ``--json /dev/null --markdown /dev/null`` is fine."""
    if is_stdout(a) or is_stdout(b):
        return is_stdout(a) and is_stdout(b)
    if output_kind(a) != "file" or output_kind(b) != "file":
        return False
    if os.path.lexists(a) and os.path.lexists(b):
        return same_file(a, b)
    return os.path.realpath(a) == os.path.realpath(b)


def refuse_shared_outputs(outputs: Mapping[str, Path | None]) -> None:
    """Refuse two options (``{"--json": path, "--rrd": path}``) that would write one file:
    the second would replace the first. Called before anything runs.

    Raises:
        MotionToolError: ``--json and --rrd both write 'X'; give each its own file``.
    """
    given = [(option, path) for option, path in outputs.items() if path is not None]
    for i, (option, path) in enumerate(given):
        for other, earlier in given[:i]:
            if _one_output(earlier, path):
                raise MotionToolError(
                    f"{other} and {option} both write '{path}'; give each its own file"
                )


def require_folder(path: Path | None, option: str) -> None:
    """Refuse a folder option (``--rrd-dir``) that names standard output, an existing path
    that is not a folder or a folder that cannot be written (a read-only file system), before
    anything runs (a missing folder is created later).

    Raises:
        MotionToolError: ``--rrd-dir 'X' is not a folder; ...``.
    """
    if path is None:
        return
    if is_stdout(path) or (os.path.exists(path) and not os.path.isdir(path)):
        raise MotionToolError(
            f"{option} '{path}' is not a folder; name a folder (it is created if missing)"
        )
    if os.path.isdir(path):  # a folder where nothing can be written: say so once, up front
        import tempfile

        try:
            tempfile.TemporaryFile(dir=path).close()
        except OSError as exc:
            raise MotionToolError(f"cannot write in '{path}': {exc.strerror or exc}") from exc
