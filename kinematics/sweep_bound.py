"""Step 2 of :mod:`motiontool.kinematics.collision`: clear a pair of joints for a whole block
of consecutive configurations at once, from one forward-kinematics evaluation.

A motion's configurations follow each other closely: over a few keyframes its motors move by
a fraction of a radian. Turning a revolute motor by δ moves a point at distance r from the motor's
origin (on its axis) by at most r·|δ|, whatever the other motors do; moving the motors one after
another from a reference configuration q0 to q, the centre of a joint's enclosing sphere moves by
at most the sum of r·|q - q0| over the motors above it, r bounded by the lengths of the kinematic
chain between them (the same in every configuration). A motor above both joints of a pair moves
them together and leaves their distance as it is. So over a block whose motors stay within δ of
q0, the distance of two joints' sphere centres is at least their distance at q0 minus
``Σ_m L[m]·δ[m]`` over the motors above one joint but not the other: where that is still more
than what the joint broad phase lets through, no configuration of the block can pass it, and the
block skips the pair. The configurations that remain take the usual path: the answer is the same,
only found with less work (a head nodding for hours is checked in a fraction of the time).
Blocks of 256 configurations are bounded first, then the blocks of 16 inside those that leave
a pair.

Revolute motors only: a model with a prismatic joint (its chains change length) is not cleared
here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.kinematics._pinocchio import PRISMATIC, KinematicTables
from motiontool.kinematics.batched_kinematics import forward_kinematics

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["SWEEP_BLOCK", "cleared_groups"]

SWEEP_BLOCK = 16
"""Consecutive configurations (8 keyframes and their segment midpoints) cleared together."""

_ROUNDING_M = 1e-9
"""Added to the bound on how far the joints can move (m): forward kinematics' rounding."""


def _lever_arms(
    tables: KinematicTables, n_motors: int
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """(nj, M) m and (nj, M) bool: for joint j and motor m above it (its own motor included),
    a bound on the distance from motor m's origin to the centre of j's enclosing sphere in
    any configuration (the chain's link lengths plus the centre's offset), and where motor m
    is above joint j."""
    import numpy as np

    nj = tables.joint_parent.shape[0]
    link = np.linalg.norm(tables.joint_translation, axis=1)
    arms = np.zeros((nj, n_motors))
    above = np.zeros((nj, n_motors), dtype=bool)
    for j in range(1, nj):
        reach, k = float(np.linalg.norm(tables.joint_center[j])), j
        while k > 0:  # up the chain: every motor on the way, at the length so far
            motor = int(tables.joint_motor[k])
            if motor >= 0:
                arms[j, motor], above[j, motor] = reach, True
            reach += float(link[k])
            k = int(tables.joint_parent[k])
    return arms, above


def _ranges(
    lo: npt.NDArray[np.float64], hi: npt.NDArray[np.float64], size: int
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The least and greatest value of each motor over each ``size`` consecutive rows of
    ``lo`` and ``hi`` (N, M) (the last block repeats its last row): (ceil(N / size), M)."""
    import numpy as np

    pad = -lo.shape[0] % size

    def blocks(a: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        return np.concatenate([a, np.repeat(a[-1:], pad, axis=0)]).reshape(-1, size, a.shape[1])

    return blocks(lo).min(axis=1), blocks(hi).max(axis=1)


class _Pairs:
    """The joint pairs ``groups`` of ``tables``, as :func:`cleared_groups` bounds them."""

    def __init__(
        self,
        tables: KinematicTables,
        groups: npt.NDArray[np.int64],
        n_motors: int,
        tolerance: float,
    ) -> None:
        import numpy as np

        self.tables = tables
        self.ja, self.jb = tables.group_joints[groups, 0], tables.group_joints[groups, 1]
        arms, above = _lever_arms(tables, n_motors)
        # A motor above both joints moves them together: only the others count.
        only_a = above[self.ja] & ~above[self.jb]
        only_b = above[self.jb] & ~above[self.ja]
        self.lever = np.where(only_a, arms[self.ja], 0.0) + np.where(only_b, arms[self.jb], 0.0)
        self.reach = tables.joint_radius[self.ja] + tables.joint_radius[self.jb] - tolerance

    def cleared(
        self, lo: npt.NDArray[np.float64], hi: npt.NDArray[np.float64]
    ) -> npt.NDArray[np.bool_]:
        """(B, G) bool: the pairs no configuration within [lo, hi] (B, M) rad brings near."""
        import numpy as np

        tables = self.tables
        rot, pos = forward_kinematics(tables, (lo + hi) / 2.0)  # (B, nj, 3, 3), (B, nj, 3)
        centers = (pos + np.einsum("bjik,jk->bji", rot, tables.joint_center)).transpose(2, 1, 0)
        gap2 = np.zeros((self.ja.shape[0], lo.shape[0]))
        for x in centers:  # x, y, z (nj, B): whole rows gathered
            d = x[self.ja] - x[self.jb]
            gap2 += d * d
        moved = self.lever @ ((hi - lo) / 2.0).T + _ROUNDING_M  # (G, B) m
        cleared: npt.NDArray[np.bool_] = (np.sqrt(gap2) - moved > self.reach[:, None]).T
        return cleared


def cleared_groups(
    tables: KinematicTables,
    q_motors: npt.NDArray[np.float64],
    groups: npt.NDArray[np.int64],
    tolerance: float,
) -> npt.NDArray[np.bool_] | None:
    """Which of the joint pairs ``groups`` (indices into ``tables.group_joints``) no
    configuration of each block of :data:`SWEEP_BLOCK` consecutive rows of ``q_motors``
    ((N, M) rad) brings within the joint broad phase's reach (their spheres overlapping by at
    least ``tolerance`` m): (ceil(N / SWEEP_BLOCK), len(groups)) bool, True where the pair
    can be skipped for the whole block. None where the model cannot be bounded this way
    (a prismatic joint).

    Blocks of :data:`SWEEP_BLOCK` ² rows are bounded first: a pair one of them clears is
    cleared for each of its blocks, which are bounded only where a pair is left."""
    import numpy as np

    if (tables.joint_kind == PRISMATIC).any() or not tables.exact:
        return None
    pairs = _Pairs(tables, groups, q_motors.shape[1], tolerance)
    lo, hi = _ranges(q_motors, q_motors, SWEEP_BLOCK)
    coarse = pairs.cleared(*_ranges(lo, hi, SWEEP_BLOCK))
    cleared = np.repeat(coarse, SWEEP_BLOCK, axis=0)[: lo.shape[0]]
    left = np.flatnonzero(~cleared.all(axis=1))
    if left.size:
        cleared[left] |= pairs.cleared(lo[left], hi[left])
    return cleared
