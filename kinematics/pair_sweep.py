"""Part of step 4 of :mod:`motiontool.kinematics.collision`: clear a pair of geometries for a
run of consecutive configurations from its depth bound at the first of them and how far each
geometry moves.

The projected-overlap bound (:mod:`motiontool.kinematics.overlap_bound`) is, along a direction
fixed in the world, ``min(hi_a - lo_b, hi_b - lo_a)`` of the two shapes' projections. If no
point of geometry ``a`` moves by more than ``D_a`` from configuration ``q0`` to ``q`` (and no
point of ``b`` by more than ``D_b``), each end of a projection moves by at most that much, so the
overlap along each of those directions, and with it the penetration depth at ``q`` (at most the
overlap along any direction), is at most the bound at ``q0`` plus ``D_a + D_b``. A point of a
geometry is its bounding sphere's centre ``c`` plus ``R u`` with ``|u| <= r``, so it moves by at
most ``|c - c0| + ||R - R0|| r``, where ``||R - R0|| = 2 sin(θ/2) = sqrt(3 - trace(R0ᵀ R))`` for
the angle θ between the two orientations.

So for each run of :data:`PAIR_SWEEP` configurations: the bound of every candidate pair at the
run's first configuration, plus the farthest each of its geometries moves in the run; a pair
for which that stays below the tolerance cannot penetrate as deep anywhere in the run, and its
candidates of the run are dropped. The others take the usual path: the contacts are the same,
found with less work (two feet a few centimetres apart through a walk, an arm beside the torso:
a long walk is checked in three quarters of the time). A depth is a true upper bound either
way; only where coal's EPA overshoots (:mod:`~motiontool.kinematics.contact_depth`) past both
bounds could a dropped pair have been reported before. Each configuration is compared with the
run's first directly, so the runs need not be of neighbours to be right, only to clear much.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.kinematics._pinocchio import KinematicTables
from motiontool.kinematics.overlap_bound import overlap_bound

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["PAIR_SWEEP", "uncleared"]

PAIR_SWEEP = 4
"""Consecutive configurations (2 keyframes and their segment midpoints) a pair is cleared for
at once (longer runs move farther and clear less); below 2, nothing is cleared here."""

_TURN_RAD = 2.0
"""A run in which a motor turns (or slides, m) farther than this from the run's first row is
not bounded here: its geometries move too far to clear a pair (a motion of random values), and
bounding it would cost time for nothing."""

_ROUNDING_M = 1e-9
"""Taken from the tolerance (m): the rounding of the bounds and of the distances moved."""


def uncleared(
    tables: KinematicTables,
    q: npt.NDArray[np.float64],
    rot: npt.NDArray[np.float64],
    centers: npt.NDArray[np.float64],
    rows: npt.NDArray[np.int64],
    pairs: npt.NDArray[np.int64],
    tolerance: float,
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """The candidates (configuration ``rows``, geometry ``pairs``) that may penetrate at least
    ``tolerance`` m deep (more than 0 where it is 0) by the bound of the module doc, runs of
    :data:`PAIR_SWEEP` rows at a time.

    Args:
        tables: the model.
        q: (N, M) the configurations, motor positions (rad or m).
        rot, centers: world orientation (N, G, 3, 3) and bounding-sphere centre (N, G, 3), m,
            of every geometry at each configuration
            (:func:`~motiontool.kinematics.batched_kinematics.geometry_poses`).
        rows, pairs: the candidates, (C,) each.
        tolerance: m, >= 0.
    """
    import numpy as np

    n = centers.shape[0]
    if PAIR_SWEEP < 2 or rows.shape[0] == 0 or n < 2:
        return rows, pairs
    tried = np.flatnonzero(_slow_runs(q)[rows // PAIR_SWEEP])
    if tried.shape[0] == 0:
        return rows, pairs
    count = tables.pair_first.shape[0]
    keys, inverse = np.unique(rows[tried] // PAIR_SWEEP * count + pairs[tried], return_inverse=True)
    run, pair = np.divmod(keys, count)  # (run, pair) of each distinct candidate
    start, moved = _moves(tables, rot, centers, run, pair)
    margin = tolerance - _ROUNDING_M - moved
    # The bound is at least minus the distance of the centres (each shape's extent >= 0): a
    # pair that moves more than that in its run stays open without computing it.
    d = centers[start, tables.pair_first[pair]] - centers[start, tables.pair_second[pair]]
    may = np.flatnonzero(np.sqrt((d * d).sum(axis=1)) > -margin)
    # The cross-product directions only where the face directions leave the pair open.
    bound = overlap_bound(tables, rot, centers, start[may], pair[may], margin[may])
    cleared = np.zeros(keys.shape[0], dtype=bool)
    cleared[may[bound < margin[may]]] = True
    keep = np.ones(rows.shape[0], dtype=bool)
    keep[tried[cleared[inverse.reshape(-1)]]] = False
    return rows[keep], pairs[keep]


def _slow_runs(q: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]:
    """Whether each run's motors all stay within :data:`_TURN_RAD` of its first row."""
    import numpy as np

    n = q.shape[0]
    turn = np.abs(q - q[np.arange(n) // PAIR_SWEEP * PAIR_SWEEP]).max(axis=1)
    slow: npt.NDArray[np.bool_] = (
        np.maximum.reduceat(turn, np.arange(0, n, PAIR_SWEEP)) <= _TURN_RAD
    )
    return slow


def _moves(
    tables: KinematicTables,
    rot: npt.NDArray[np.float64],
    centers: npt.NDArray[np.float64],
    run: npt.NDArray[np.int64],
    pair: npt.NDArray[np.int64],
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64]]:
    """For each (``run``, ``pair``): the run's first row, and the farthest a point of the pair's
    first geometry moves from there in the run plus the same for its second, m."""
    import numpy as np

    n = centers.shape[0]
    runs, run_of = np.unique(run, return_inverse=True)
    geoms, geom_of = np.unique(
        np.concatenate([tables.pair_first[pair], tables.pair_second[pair]]), return_inverse=True
    )
    first = runs * PAIR_SWEEP
    each = np.minimum(first[:, None] + np.arange(PAIR_SWEEP), n - 1)  # (runs, PAIR_SWEEP)
    r0, c0 = rot[first[:, None], geoms], centers[first[:, None], geoms]  # (runs, g, ...)
    r, c = rot[each[:, :, None], geoms], centers[each[:, :, None], geoms]
    shift = c - c0[:, None]
    moved = np.sqrt((shift * shift).sum(axis=3))
    trace = (r * r0[:, None]).sum(axis=(3, 4))
    moved += np.sqrt(np.clip(3.0 - trace, 0.0, None)) * tables.geom_radius[geoms]
    reach = moved.max(axis=1)  # (runs, g): the farthest in each run
    run_of, geom_of = run_of.reshape(-1), geom_of.reshape(-1)
    both = reach[run_of, geom_of[: run.shape[0]]] + reach[run_of, geom_of[run.shape[0] :]]
    return first[run_of], both
