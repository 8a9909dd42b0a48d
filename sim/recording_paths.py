"""Paths kept bounded however long the run: the root body's whole path in a recording and the
tool's trail in a report, thinned by a stride that doubles as the run goes on
(:class:`Thinned`); a row of the tool's growing trail in a recording cut to a number of points
(:func:`thin`). Numpy only."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["Thinned", "thin"]


class Thinned:
    """Points of consecutive frames, thinned to at most ``most``: the frames that are a
    multiple of a stride that doubles whenever they would be more."""

    def __init__(self, most: int) -> None:
        self.most, self.stride = most, 1
        self.frames: list[npt.NDArray[np.int64]] = []
        self.rows: list[npt.NDArray[np.float64]] = []
        self.count = 0

    def add(self, first: int, points: npt.NDArray[np.float64]) -> None:
        """Points of the frames ``first``, ``first + 1``, ... ."""
        import numpy as np

        frames = np.arange(first, first + len(points))
        keep = frames % self.stride == 0
        self.frames.append(frames[keep])
        self.rows.append(points[keep].copy())
        self.count += int(keep.sum())
        while self.count > self.most:
            self.stride *= 2
            kept = [(f % self.stride == 0) for f in self.frames]
            self.frames = [f[k] for f, k in zip(self.frames, kept, strict=True)]
            self.rows = [r[k] for r, k in zip(self.rows, kept, strict=True)]
            self.count = sum(len(f) for f in self.frames)
        if len(self.rows) > 64:  # few arrays: join them
            self.frames, self.rows = [np.concatenate(self.frames)], [np.concatenate(self.rows)]

    def kept(self, width: int = 3) -> npt.NDArray[np.float64]:
        """The points kept, (n, ``width``)."""
        import numpy as np

        return np.concatenate(self.rows) if self.rows else np.empty((0, width))

    def points(self, last_frame: int, last: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """The points kept, and the last frame's ``last`` if it was not."""
        import numpy as np

        rows = self.kept(last.shape[0])
        frames = np.concatenate(self.frames) if self.frames else np.empty(0, dtype=np.int64)
        if not len(frames) or frames[-1] != last_frame:
            rows = np.concatenate([rows, last[None, :]])
        return rows


def thin(path: npt.NDArray[np.float64], most: int) -> npt.NDArray[np.float64]:
    """``path`` with at most ``most`` points: every n-th one and the last."""
    n = len(path)
    if n <= most:
        return path
    every = math.ceil(n / (most - 1))
    kept = path[::every]
    return kept if (n - 1) % every == 0 else path[[*range(0, n, every), n - 1]]
