"""Small numpy idioms that several modules need, spelt once."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["sorted_distinct"]


def sorted_distinct(values: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
    """The sorted distinct values of a 1-D integer array, as ``np.unique`` gives them, by a sort
    and a comparison with the neighbour: ``np.unique`` hashes (holding about 3 times the
    array) and, in numpy 2.4, imports ``numpy.ma`` on first use (25 ms of a pre-commit run)."""
    import numpy as np

    ordered = np.sort(values)
    if ordered.shape[0] == 0:
        return ordered
    return ordered[np.concatenate(([True], ordered[1:] != ordered[:-1]))]
