"""The frozen, array-backed view of a motion: what a robot is asked to do."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.motionfmt.pose_names import PoseNames

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["Motion"]


@dataclass(frozen=True, eq=False)
class Motion:
    """A motion as Webots plays it.

    Attributes:
        joints: J joint (motor) names, in column order; a name may appear twice (the later
            column wins on the robot).
        pose_names: P pose names: a tuple, or the :class:`PoseNames` of a read (kept as they
            are: a few bytes a name).
        times_ms: int64 array, shape (P,), strictly increasing pose times in milliseconds.
        values: float64 array, shape (P, J): joint targets in radians (metres for linear
            joints); NaN where the cell is ``*`` (no command) or Webots' -9999999.9 marker, and
            also where the cell is a literal ``nan`` (a command: Webots sends NaN to the motor).
            ``commanded`` tells the two apart.
        commanded: bool array, shape (P, J): True where the cell is a command (a number,
            ``nan`` and ``inf`` included), False for ``*`` and the -9999999.9 marker. When a
            Motion is built without it, it is derived as ``~isnan(values)`` (every NaN is then
            ``*``), as before this mask existed. ``values`` is NaN wherever ``commanded`` is
            False.

    The arrays are read-only. A read-only int64 ``times_ms`` or float64 ``values`` array is
    kept as it is (no one can write it: a read's own arrays, shared, not copied); any other is
    copied.
    """

    joints: tuple[str, ...]
    pose_names: Sequence[str]
    times_ms: npt.NDArray[np.int64]
    values: npt.NDArray[np.float64]
    commanded: npt.NDArray[np.bool_] = None  # type: ignore[assignment]  # derived when None

    def __post_init__(self) -> None:
        import numpy as np

        times = np.array(
            self.times_ms, dtype=np.int64, copy=not _read_only(self.times_ms, np.int64)
        )
        given = self.values
        shared = _read_only(given, np.float64)
        values = np.array(given, dtype=np.float64, copy=not shared)
        values = values.reshape(len(times), len(self.joints))
        if self.commanded is None:
            commanded = ~np.isnan(values)
        else:
            commanded = np.array(self.commanded, dtype=np.bool_)
            if commanded.shape != values.shape:
                raise ValueError(f"commanded has shape {commanded.shape}, values {values.shape}")
            idle = ~commanded
            if not bool(np.isnan(values[idle]).all()):
                if shared:
                    values = values.copy()
                values[idle] = np.nan
        times.flags.writeable = False
        values.flags.writeable = False
        commanded.flags.writeable = False
        object.__setattr__(self, "times_ms", times)
        object.__setattr__(self, "values", values)
        object.__setattr__(self, "commanded", commanded)
        object.__setattr__(self, "joints", tuple(self.joints))
        if not isinstance(self.pose_names, PoseNames):
            object.__setattr__(self, "pose_names", tuple(self.pose_names))
        if len(self.pose_names) != len(times):
            raise ValueError(f"{len(self.pose_names)} pose names for {len(times)} poses")
        if len(times) == 0 or len(self.joints) == 0:
            raise ValueError("a motion needs at least one joint and one pose")
        if len(times) > 1 and not bool(np.all(np.diff(times) > 0)):
            raise ValueError("pose times must strictly increase")

    @property
    def n_poses(self) -> int:
        """P, the number of poses."""
        return int(self.times_ms.shape[0])

    @property
    def n_joints(self) -> int:
        """J, the number of joint columns."""
        return len(self.joints)

    @property
    def duration_ms(self) -> int:
        """The last pose's time in milliseconds (Webots' ``wbu_motion_get_duration``)."""
        return int(self.times_ms[-1])

    def column(self, joint: str) -> int:
        """Index of the column that drives ``joint`` on the robot (the last one of that name)."""
        for j in range(len(self.joints) - 1, -1, -1):
            if self.joints[j] == joint:
                return j
        raise KeyError(joint)

    def __eq__(self, other: object) -> bool:
        import numpy as np

        if not isinstance(other, Motion):
            return NotImplemented
        return (
            self.joints == other.joints
            and self.pose_names == other.pose_names
            and np.array_equal(self.times_ms, other.times_ms)
            and np.array_equal(self.values, other.values, equal_nan=True)
            and np.array_equal(self.commanded, other.commanded)
        )

    __hash__ = None  # type: ignore[assignment]


def _read_only(given: object, dtype: type[np.generic]) -> bool:
    """Whether ``given`` is a numpy array of ``dtype`` that no one can write."""
    import numpy as np

    return isinstance(given, np.ndarray) and given.dtype == dtype and not given.flags.writeable
