"""Samples of joint positions (a recording's, or curves sampled at the control step) made a
motion: on whole ms, the keyframes reduced by the same reduction as ``resample --max-error``
(:func:`~motiontool.motionfmt.resample.resample`), and how far the motion is from the samples.
What a ROS 2 bag (:mod:`.rosbag`) and Choregraphe's curves (:mod:`.choregraphe`) read become."""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.motionfmt.convert.base import Deviation
from motiontool.motionfmt.writer import pose_name

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["deviation_at", "reduced"]


def reduced(
    joints: tuple[str, ...],
    t_ms: npt.NDArray[np.float64],
    q: npt.NDArray[np.float64],
    max_error: float,
    path: str,
) -> tuple[Motion, int]:
    """The samples at ``t_ms`` (ms, increasing, float64 (M,)) of ``q`` (float64 (M, J), rad or
    m) on whole ms (the first sample of each ms), their keyframes reduced within ``max_error``
    (rad) as ``resample --max-error`` reduces them; (motion, samples left out on a shared ms)."""
    import numpy as np

    from motiontool.motionfmt.document import loads
    from motiontool.motionfmt.motion import Motion
    from motiontool.motionfmt.resample import resample
    from motiontool.motionfmt.writer import format_motion

    ms = np.rint(t_ms).astype(np.int64)
    keep = np.concatenate(([True], np.diff(ms) > 0))
    times = ms[keep]
    values = q[keep]
    full = Motion(
        joints,
        tuple(pose_name(int(t)) for t in times),
        times,
        values,
        np.ones(values.shape, dtype=bool),
    )
    doc = loads(format_motion(full).encode("utf-8", "surrogateescape"), path)
    return resample(doc, max_error=max_error).document.motion, int((~keep).sum())


def deviation_at(
    motion: Motion, t_ms: npt.NDArray[np.float64], q: npt.NDArray[np.float64], compared: str
) -> Deviation:
    """The motion's straight lines at every time of ``t_ms`` (ms, float64 (M,)) against ``q``
    (float64 (M, J), the motion's joints), rad; ``compared`` says what was compared."""
    import numpy as np

    key_t = motion.times_ms.astype(np.float64)
    err = np.empty_like(q)
    for j in range(q.shape[1]):
        err[:, j] = np.abs(np.interp(t_ms, key_t, motion.values[:, j]) - q[:, j])
    at = np.unravel_index(int(np.argmax(err)), err.shape)
    return Deviation(
        float(err[at]), motion.joints[int(at[1])], round(float(t_ms[int(at[0])])), compared
    )
