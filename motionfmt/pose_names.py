"""The pose names of a motion, held as text: :class:`PoseNames`.

A list of P names holds a ``str`` object and a pointer per name, about 60 bytes for a name of
ten characters; a file of millions of poses spends more on its names than on its values. Here
the names are joined, :data:`CHUNK` at a time, into one string each, with a newline between
them (a pose name never holds one: Webots cuts a line's tokens at ``,``, ``\\n`` and ``\\r``):
a byte or two more than the characters themselves.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence
from typing import overload

__all__ = ["CHUNK", "PoseNames"]

CHUNK = 4096
"""Names joined into one string."""


class PoseNames(Sequence[str]):
    """P pose names, in order: a sequence of ``str`` equal to any sequence of the same names.

    Read in order (a report, a write), each chunk is split once; a name far from the last one
    read costs the split of its chunk (a few tens of microseconds). Threads may read one at
    once (the chunk split last is swapped whole); adding is for one thread.

    Raises:
        ValueError: (:meth:`append`, :meth:`extend`) a name holds a newline.
    """

    __slots__ = ("_chunks", "_last", "_pending")

    def __init__(self, names: Iterable[str] = ()) -> None:
        self._chunks: list[str] = []  # CHUNK names each, joined by newlines
        self._pending: list[str] = []  # the names after the last full chunk
        self._last: tuple[int, list[str]] = (-1, [])  # the chunk split last
        self.extend(names)

    def append(self, name: str) -> None:
        """Add ``name`` after the others."""
        if "\n" in name:
            raise ValueError(f"a pose name holds a newline: {name!r}")
        self._pending.append(name)
        if len(self._pending) == CHUNK:
            self._flush()

    def extend(self, names: Iterable[str]) -> None:
        """Add ``names`` after the others, in order (none of them if one holds a newline)."""
        if names is self:
            names = list(names)
        if isinstance(names, PoseNames):
            for chunk in names._chunks:
                self._add(chunk.split("\n"))
            self._add(names._pending)
            return
        given = names if isinstance(names, list) else list(names)
        if "\n".join(given).count("\n") != max(len(given) - 1, 0):
            bad = next(name for name in given if "\n" in name)
            raise ValueError(f"a pose name holds a newline: {bad!r}")
        self._add(given)

    def _add(self, names: list[str]) -> None:
        """Add ``names``, none of which holds a newline."""
        at = 0
        while at < len(names):
            room = CHUNK - len(self._pending)
            self._pending.extend(names[at : at + room])
            at += room
            if len(self._pending) == CHUNK:
                self._flush()

    def _flush(self) -> None:
        self._chunks.append("\n".join(self._pending))
        self._pending = []

    def _chunk(self, k: int) -> list[str]:
        if k == len(self._chunks):
            return self._pending
        last = self._last  # one read: another thread may split another chunk meanwhile
        if last[0] != k:
            last = self._last = (k, self._chunks[k].split("\n"))
        return last[1]

    def __len__(self) -> int:
        return len(self._chunks) * CHUNK + len(self._pending)

    @overload
    def __getitem__(self, index: int) -> str: ...

    @overload
    def __getitem__(self, index: slice) -> list[str]: ...

    def __getitem__(self, index: int | slice) -> str | list[str]:
        """The name at ``index``, or a list of the names of a slice."""
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self)))]
        n = len(self)
        i = index + n if index < 0 else index
        if not 0 <= i < n:
            raise IndexError(f"pose {index} of {n}")
        return self._chunk(i // CHUNK)[i % CHUNK]

    def index(self, value: object, start: int = 0, stop: int | None = None) -> int:
        """The first pose from ``start`` (up to ``stop``) named ``value``; ValueError if none."""
        lo, hi, _ = slice(start, stop).indices(len(self))
        for k in range(lo // CHUNK, -(-hi // CHUNK)):
            base = k * CHUNK
            names = self._chunk(k)
            if value in names[max(lo - base, 0) : hi - base]:
                return base + names.index(value, max(lo - base, 0), hi - base)
        raise ValueError(f"{value!r} is not a pose name")

    def __iter__(self) -> Iterator[str]:
        for chunk in self._chunks:
            yield from chunk.split("\n")
        yield from self._pending

    def __eq__(self, other: object) -> bool:
        if isinstance(other, PoseNames):
            return self._chunks == other._chunks and self._pending == other._pending
        if not isinstance(other, Sequence) or isinstance(other, str | bytes):
            return NotImplemented
        return len(self) == len(other) and all(a == b for a, b in zip(self, other, strict=True))

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        shown = ", ".join(repr(name) for name in self[:3])
        return f"PoseNames([{shown}{', ...' if len(self) > 3 else ''}], {len(self)} names)"
