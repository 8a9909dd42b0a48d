"""A file's findings made on demand: never all held, whatever the file's size.

A robot check of a 26 MB file with random values finds 3.5 million problems; held as objects
they take gigabytes. The checks keep what they computed as arrays (a few bytes a cell) and make
each finding when a report reaches it: :class:`Findings` is a sequence whose findings are made
every time it is read, in file order (:meth:`Diagnostic.sort_key`), so that a report streams
them to its output one at a time. Reading it again makes them again (a report that needs two
passes, such as the JUnit report whose counts come first, pays twice the time, never the
memory). The first whole pass also counts them by severity (:meth:`Findings.count`), so the
summary and the exit code that follow a report need no pass of their own.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, overload

from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.finding_log import FindingLog

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["Findings", "in_order"]


class Findings(Sequence[Diagnostic]):
    """Findings in file order, made each time they are read.

    ``make()`` returns an iterable of the findings, sorted by :meth:`Diagnostic.sort_key`
    (stable: findings at one place keep the order they are made in). Indexing and ``len``
    read them all (for tests and small files); a report iterates.
    """

    __slots__ = ("_counts", "_make")

    def __init__(self, make: Callable[[], Iterable[Diagnostic]]) -> None:
        self._make = make
        self._counts: dict[Severity, int] | None = None

    @classmethod
    def of(cls, findings: Iterable[Diagnostic]) -> Findings:
        """Findings already made (a list, sorted here): what a small check returns."""
        if isinstance(findings, Findings):
            return findings
        if isinstance(findings, FindingLog):  # the reader's: sorted a chunk at a time
            return cls(findings.in_order)
        held = sorted(findings, key=Diagnostic.sort_key)
        return cls(lambda: held)

    @classmethod
    def merge(cls, parts: Sequence[Iterable[Diagnostic]]) -> Findings:
        """The findings of ``parts`` (each a :class:`Findings` or a list) in one file order;
        at one place, those of an earlier part first (as a stable sort of them all)."""
        sorted_parts = [cls.of(p) for p in parts]
        if len(sorted_parts) == 1:
            return sorted_parts[0]
        return cls(lambda: heapq.merge(*sorted_parts, key=Diagnostic.sort_key))

    def where(self, keep: Callable[[Diagnostic], bool]) -> Findings:
        """The findings ``keep`` keeps, in the same order, made as these are."""
        return Findings(lambda: (d for d in self._make() if keep(d)))

    def __iter__(self) -> Iterator[Diagnostic]:
        if self._counts is not None:
            yield from self._make()
            return
        counts = dict.fromkeys(Severity, 0)
        for d in self._make():
            counts[d.severity] += 1
            yield d
        self._counts = counts  # a whole pass: the counts are known from now on

    @property
    def counts(self) -> dict[Severity, int] | None:
        """How many findings of each severity, once a whole pass has made them (else None)."""
        return None if self._counts is None else dict(self._counts)

    def know(self, counts: dict[Severity, int]) -> None:
        """Take ``counts`` (:attr:`counts` of findings made the same way, by a pass before
        these were made again) as this sequence's counts, so that counting needs no pass."""
        self._counts = dict(counts)

    def count(self, severity: Severity) -> int:
        """How many findings of ``severity`` (a pass over them the first time only)."""
        if self._counts is None:
            for _ in self:
                pass
        assert self._counts is not None
        return self._counts[severity]

    def __len__(self) -> int:
        return sum(self.count(s) for s in Severity)

    def __bool__(self) -> bool:
        if self._counts is not None:
            return any(self._counts.values())
        return next(iter(self._make()), None) is not None

    @overload
    def __getitem__(self, index: int) -> Diagnostic: ...
    @overload
    def __getitem__(self, index: slice) -> list[Diagnostic]: ...
    def __getitem__(self, index: int | slice) -> Diagnostic | list[Diagnostic]:
        return list(self)[index]

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Findings | list | tuple):
            return list(self) == list(other)
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"Findings({list(self)!r})"


def in_order(
    poses: npt.NDArray[np.integer],
    columns: npt.NDArray[np.integer],
    make: Callable[[int], Diagnostic],
) -> Findings:
    """Findings made by ``make(i)`` for each ``i`` of ``range(len(poses))``, in file order: the
    ``i``-th is on pose ``poses[i]`` (a line each, in order) at file column ``columns[i]`` (-1:
    the time token). A check that knows where its findings are from its arrays sorts the places
    once (an int a finding) and makes each finding when it is read, of one code at one place at
    most (ties keep ``i``'s order)."""
    import numpy as np

    order = np.lexsort((columns, poses))
    return Findings(lambda: _each(order, make))


def _each(order: npt.NDArray[np.intp], make: Callable[[int], Diagnostic]) -> Iterator[Diagnostic]:
    step = 65536  # indices turned into Python ints a block at a time
    for start in range(0, order.shape[0], step):
        for i in order[start : start + step].tolist():
            yield make(i)
