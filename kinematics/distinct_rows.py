"""The distinct configurations of a block of a motion, found by their bytes: identical
configurations (a motion holding still, a cycle met again) are checked once
(:mod:`motiontool.kinematics.collision`, step 1)."""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["distinct_rows"]


@functools.cache
def _hash_weights(n_motors: int) -> npt.NDArray[np.uint64]:
    """Odd 64-bit multipliers, one per motor (a fixed seed: the same hashes in every run)."""
    import numpy as np

    weights = np.random.default_rng(0x6D6F74).integers(0, 2**63, n_motors, dtype=np.uint64)
    return weights * np.uint64(2) + np.uint64(1)


def distinct_rows(
    q: npt.NDArray[np.float64],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.uint64]]:
    """The distinct rows of ``q`` (equal bytes) in first-seen order, each row's index among
    them (identical configurations are checked once), and a hash of each distinct row."""
    import numpy as np

    bits = np.ascontiguousarray(q).view(np.uint64)
    mixed = bits ^ (bits >> np.uint64(29))
    hashed = (mixed * _hash_weights(q.shape[1])).sum(axis=1, dtype=np.uint64)  # mod 2**64
    _values, first, inverse = np.unique(hashed, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    if not (bits == bits[first[inverse]]).all():  # two rows share a hash: compare the bytes
        return _distinct_rows_exact(q)
    order = np.argsort(first)  # the distinct rows in the order met
    rank = np.empty_like(order)
    rank[order] = np.arange(order.shape[0])
    firsts = first[order]
    return q[firsts], rank[inverse], hashed[firsts]


def _distinct_rows_exact(
    q: npt.NDArray[np.float64],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.uint64]]:
    """:func:`distinct_rows` by the rows' bytes, one at a time (Python's hash of them)."""
    import numpy as np

    index_of: dict[bytes, int] = {}
    firsts: list[int] = []
    inverse = np.empty(q.shape[0], dtype=np.int64)
    for i, row in enumerate(q):
        k = index_of.setdefault(row.tobytes(), len(firsts))
        if k == len(firsts):
            firsts.append(i)
        inverse[i] = k
    hashed = np.array([hash(key) % 2**64 for key in index_of], dtype=np.uint64)
    return q[firsts], inverse, hashed
