"""Transforming motions without losing anything: resample onto a grid, drop keyframes, retime.

Everything edits a lossless :class:`~motiontool.motionfmt.document.MotionDocument`, so the lines
and cells a transform keeps keep their original spelling; new poses are spelt canonically. One
module per transform, re-exported here:

* :mod:`.resample`: :func:`resample` puts keyframes on a uniform grid of pose times and, with
  ``max_error``, removes the keyframes that the command stream does not need, losslessly where
  the grid holds every original pose time (to :data:`ROUNDING_RAD`).
* :mod:`.retime`: :func:`scale_times` and :func:`fit_duration` change pose times only, never
  values, in whole milliseconds, always strictly increasing (:class:`Retimed`).
* :mod:`.fit_limits`: :func:`fit_limits` stretches the segments too fast for a joint's velocity
  (and acceleration) limit.

Pure numpy: no robot knowledge. Velocity limits come in as ``{joint name: max velocity}``.
"""

from __future__ import annotations

from motiontool.motionfmt.fit_limits import DEFAULT_MARGIN, fit_limits
from motiontool.motionfmt.resample import ROUNDING_RAD, Resampled, grid_times, resample
from motiontool.motionfmt.retime import (
    MAX_TIME_MS,
    Retimed,
    Stretch,
    TimeOverflowError,
    fit_duration,
    scale_times,
)

__all__ = [
    "DEFAULT_MARGIN",
    "MAX_TIME_MS",
    "ROUNDING_RAD",
    "Resampled",
    "Retimed",
    "Stretch",
    "TimeOverflowError",
    "fit_duration",
    "fit_limits",
    "grid_times",
    "resample",
    "scale_times",
]
