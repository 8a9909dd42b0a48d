"""The distinct configurations of a block of a motion, found by their bytes, and the memo of
the configurations met in earlier blocks: identical configurations (a motion holding still, a
cycle met again) are checked once (:mod:`motiontool.kinematics.collision`, step 1).

A row's hash is a sum over its columns (mod 2**64) of each value's mixed bits times a weight of
its column, so the columns that hold one value in the whole block add one constant: only the
columns that change are hashed and compared row by row (a motion of the head costs two columns
of work, not the robot's 26).
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["Contacts", "Known", "distinct_rows"]

Contacts = tuple[tuple[str, str, float], ...]
"""The contacts at one configuration: (body_a, body_b, depth m), sorted by bodies."""


@functools.cache
def _hash_weights(n_motors: int) -> npt.NDArray[np.uint64]:
    """Odd 64-bit multipliers, one per motor: SplitMix64 from a fixed seed (the same hashes in
    every run; ``numpy.random`` would cost a pre-commit run its import)."""
    import numpy as np

    mask, state, weights = 2**64 - 1, 0x6D6F74, []
    for _ in range(n_motors):
        state = (state + 0x9E3779B97F4A7C15) & mask
        z = ((state ^ (state >> 30)) * 0xBF58476D1CE4E5B9) & mask
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & mask
        weights.append((z ^ (z >> 31)) | 1)
    return np.array(weights, dtype=np.uint64)


def _hash(bits: npt.NDArray[np.uint64], weights: npt.NDArray[np.uint64]) -> npt.NDArray[np.uint64]:
    """(n,) the hash of each row of ``bits`` (n, k) over its k columns of ``weights``."""
    import numpy as np

    mixed = bits ^ (bits >> np.uint64(29))
    hashed: npt.NDArray[np.uint64] = (mixed * weights).sum(axis=1, dtype=np.uint64)  # mod 2**64
    return hashed


def distinct_rows(
    q: npt.NDArray[np.float64],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.uint64]]:
    """The distinct rows of ``q`` (N, M) (equal bytes) in first-seen order, each row's index
    among them (identical configurations are checked once), and each distinct row's hash
    (the same for the same bytes in every call)."""
    import numpy as np

    bits = np.ascontiguousarray(q).view(np.uint64)
    weights = _hash_weights(q.shape[1])
    changing = (bits != bits[:1]).any(axis=0)
    held = _hash(bits[:1, ~changing], weights[~changing])[0]  # the same in every row
    moving = bits[:, changing]
    hashed = _hash(moving, weights[changing]) + held
    ordered = np.sort(hashed)
    if not (ordered[1:] == ordered[:-1]).any():  # every row its own (a motion that never
        return q, np.arange(q.shape[0]), hashed  # stops or comes back): nothing to gather
    _values, first, inverse = np.unique(hashed, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    if not (moving == moving[first[inverse]]).all():  # rows that share a hash: by the bytes
        return _distinct_rows_exact(q, bits, weights)
    order = np.argsort(first)  # the distinct rows in the order met
    rank = np.empty_like(order)
    rank[order] = np.arange(order.shape[0])
    firsts = first[order]
    return q[firsts], rank[inverse], hashed[firsts]


def _distinct_rows_exact(
    q: npt.NDArray[np.float64], bits: npt.NDArray[np.uint64], weights: npt.NDArray[np.uint64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.uint64]]:
    """:func:`distinct_rows` by the rows' bytes, one row at a time (``bits``: ``q``'s)."""
    import numpy as np

    index_of: dict[bytes, int] = {}
    firsts: list[int] = []
    inverse = np.empty(q.shape[0], dtype=np.int64)
    for i, row in enumerate(q):
        k = index_of.setdefault(row.tobytes(), len(firsts))
        if k == len(firsts):
            firsts.append(i)
        inverse[i] = k
    return q[firsts], inverse, _hash(bits[firsts], weights)


class Known:
    """A memo of :func:`~motiontool.kinematics.collision.scan_self_collisions`, shared by the
    calls that scan one motion a block at a time: the contacts at each configuration met, with
    the configuration's bytes, by its hash (two configurations may share one: the bytes tell
    them apart)."""

    def __init__(self) -> None:
        self._by_hash: dict[int, tuple[bytes, Contacts]] = {}
        self._sorted: npt.NDArray[np.uint64] | None = None  # the hashes, while up to date

    def __len__(self) -> int:
        return len(self._by_hash)

    def remember(self, hashed: int, row: bytes, contacts: Contacts) -> None:
        """Keep the contacts at the configuration of bytes ``row`` (the first of a hash)."""
        if hashed not in self._by_hash:
            self._by_hash[hashed] = (row, contacts)
            self._sorted = None

    def split(
        self, unique: npt.NDArray[np.float64], hashed: npt.NDArray[np.uint64]
    ) -> tuple[npt.NDArray[np.int64], dict[int, Contacts]]:
        """The rows of ``unique`` (of hashes ``hashed``) not met before, and the contacts of
        those met before (the rows that have any)."""
        import numpy as np

        known: dict[int, Contacts] = {}
        new = np.ones(unique.shape[0], dtype=bool)
        if not self._by_hash:
            return np.flatnonzero(new), known
        if self._sorted is None:
            self._sorted = np.sort(np.fromiter(self._by_hash, np.uint64, len(self._by_hash)))
        at = np.searchsorted(self._sorted, hashed).clip(max=self._sorted.shape[0] - 1)
        for i in np.flatnonzero(self._sorted[at] == hashed).tolist():  # then by the bytes
            row, contacts = self._by_hash[int(hashed[i])]
            if row == unique[i].tobytes():
                new[i] = False
                if contacts:
                    known[i] = contacts
        return np.flatnonzero(new), known
