"""The reader's findings, kept in bounded memory however many a file has.

A file with a unit on every cell (``0.5rad``) has a finding a cell: 2.6 million for a 26 MB
file, half a kilobyte each as objects: 1.3 GB. :class:`FindingLog` is the list the reader
appends them to: it holds the last :data:`HELD` of them at most, and writes the earlier ones, a
chunk at a time (pickled, compressed), to an unnamed temporary file, from which each pass reads
them back a chunk at a time. A file with fewer than :data:`HELD` findings (every file people
write by hand) never opens one.

The reader appends in file order but for a few findings made after the poses (the checks of
the whole motion): :meth:`FindingLog.in_order` merges the runs of findings already in order, a
chunk of each at a time, into the order a stable sort gives.
"""

from __future__ import annotations

import heapq
import itertools
import sys
import threading
from collections.abc import Iterable, Iterator, Sequence
from typing import IO, overload

from motiontool.motionfmt.diagnostics import Diagnostic

__all__ = ["CHUNK", "HELD", "FindingLog"]

CHUNK = 8192
"""Findings written to (and read back from) the temporary file at a time."""

HELD = 8 * CHUNK
"""Findings held in memory at most (about 35 MB): past this, the oldest :data:`CHUNK` are
written out. Each pass over findings on disk makes them again (about 3 µs each): a file with
fewer findings keeps them all, as a list would, and pays nothing."""


class FindingLog(Sequence[Diagnostic]):
    """An append-only sequence of findings, the oldest beyond :data:`HELD` on disk.

    It reads like a list (``len``, indexing, iteration in the order appended, ``==`` with any
    sequence of findings); ``del log[n:]`` takes back the last ones appended.
    """

    def __init__(self, findings: Iterable[Diagnostic] = ()) -> None:
        self._held: list[Diagnostic] = []
        self._size, self._most = CHUNK, HELD  # this log's: it reads back what it wrote
        self._file: IO[bytes] | None = None
        self._chunks: list[tuple[int, int]] = []  # (offset, length) in the file, a chunk each
        self._runs: list[int] = [0]  # where each run of findings in file order starts
        self._last_key: tuple[str, int, int, str] | None = None
        self._lock = threading.Lock()  # a chunk's seek and read go together
        for d in findings:
            self.append(d)

    @property
    def _spilled(self) -> int:
        return len(self._chunks) * self._size

    def append(self, finding: Diagnostic) -> None:
        key = finding.sort_key()
        if self._last_key is not None and key < self._last_key:
            self._runs.append(len(self))
        self._last_key = key
        self._held.append(finding)
        if len(self._held) >= self._most:
            self._spill()

    def _spill(self) -> None:
        """Write the oldest chunk of held findings to the file; where no temporary file can be
        written (no space, no writable folder), hold them all from now on, as a list would."""
        import pickle
        import zlib

        blob = zlib.compress(pickle.dumps(self._held[: self._size], pickle.HIGHEST_PROTOCOL), 1)
        offset = self._chunks[-1][0] + self._chunks[-1][1] if self._chunks else 0
        try:
            if self._file is None:
                import tempfile
                import weakref

                # Kept open for the log's life, closed by the finalizer below.
                self._file = tempfile.TemporaryFile(prefix="motiontool-findings-")  # noqa: SIM115
                weakref.finalize(self, self._file.close)  # closed (and gone) with the log
            with self._lock:
                self._file.seek(offset)
                self._file.write(blob)
                self._file.flush()
        except OSError:
            self._most = sys.maxsize
            return
        self._chunks.append((offset, len(blob)))
        del self._held[: self._size]

    def _chunk(self, k: int) -> list[Diagnostic]:
        """Chunk ``k`` of the file."""
        import pickle
        import zlib

        assert self._file is not None
        offset, length = self._chunks[k]
        with self._lock:
            self._file.seek(offset)
            blob = self._file.read(length)
        chunk: list[Diagnostic] = pickle.loads(zlib.decompress(blob))
        return chunk

    def __len__(self) -> int:
        return self._spilled + len(self._held)

    def __iter__(self) -> Iterator[Diagnostic]:
        return self._between(0, len(self))

    def _between(self, start: int, stop: int) -> Iterator[Diagnostic]:
        """The findings ``start`` to ``stop`` (exclusive), a chunk read at a time."""
        at = start
        while at < min(stop, self._spilled):
            k = at // self._size
            chunk = self._chunk(k)
            end = min(stop, (k + 1) * self._size)
            yield from chunk[at - k * self._size : end - k * self._size]
            at = end
        held_from = self._spilled
        if stop > held_from:
            yield from self._held[max(at, held_from) - held_from : stop - held_from]

    def in_order(self) -> Iterator[Diagnostic]:
        """The findings sorted by :meth:`Diagnostic.sort_key`, stable (those at one place in
        the order appended): the runs in file order merged."""
        bounds = [*self._runs, len(self)]
        runs = [self._between(a, b) for a, b in itertools.pairwise(bounds)]
        if len(runs) == 1:
            return runs[0]
        return heapq.merge(*runs, key=Diagnostic.sort_key)

    @overload
    def __getitem__(self, index: int) -> Diagnostic: ...
    @overload
    def __getitem__(self, index: slice) -> list[Diagnostic]: ...
    def __getitem__(self, index: int | slice) -> Diagnostic | list[Diagnostic]:
        if isinstance(index, slice):
            start, stop, step = index.indices(len(self))
            if step != 1:
                return list(self)[index]
            return list(self._between(start, max(start, stop)))
        i = range(len(self))[index]  # IndexError out of range
        if i >= self._spilled:
            return self._held[i - self._spilled]
        return self._chunk(i // self._size)[i % self._size]

    def __delitem__(self, index: slice) -> None:
        """``del log[n:]``: the findings from ``n`` on are taken back (the only deletion)."""
        start, stop, step = index.indices(len(self))
        if step != 1 or stop != len(self):
            raise TypeError("only the last findings appended can be taken back: del log[n:]")
        while start < self._spilled:  # bring the chunk that holds it back into memory
            self._held[:0] = self._chunk(len(self._chunks) - 1)
            offset, _length = self._chunks.pop()
            assert self._file is not None
            with self._lock:
                self._file.truncate(offset)
        del self._held[start - self._spilled :]
        while len(self._runs) > 1 and self._runs[-1] >= len(self):
            self._runs.pop()
        self._last_key = self[len(self) - 1].sort_key() if len(self) else None

    def __eq__(self, other: object) -> bool:
        if isinstance(other, FindingLog | list | tuple):
            return len(self) == len(other) and all(a == b for a, b in zip(self, other, strict=True))
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def __reduce__(self) -> tuple[type[FindingLog], tuple[list[Diagnostic]]]:
        return (FindingLog, (list(self),))  # a copy for another process: no file to share

    def __repr__(self) -> str:
        return (
            f"FindingLog({list(self)!r})"
            if len(self) <= self._size
            else f"<FindingLog {len(self)}>"
        )
