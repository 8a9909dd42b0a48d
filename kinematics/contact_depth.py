"""Step 5 of :mod:`motiontool.kinematics.collision`: the depth of the candidates that the
bounds leave, measured by coal, and the deepest of each pair of bodies at each configuration.

A report names a pair of bodies once per configuration, at the depth of its deepest geometry
pair, so the geometry pairs of one pair of bodies are measured deepest bound first: one whose
bound is no deeper than a depth already found cannot be the deepest, and is not measured (coal
measures about half the candidates of a motion with random values).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.kinematics import _pinocchio
from motiontool.kinematics._pinocchio import KinematicTables
from motiontool.kinematics.robots import RobotSpec

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["body_ids", "deepest_by_row", "deepest_first"]


def body_ids(bodies: tuple[str, ...]) -> npt.NDArray[np.int64]:
    """Each geometry's body as its index among the bodies' names sorted (min and max of two
    ids are those of their names)."""
    import numpy as np

    names = sorted(set(bodies))
    return np.array([names.index(b) for b in bodies], dtype=np.int64)


def _bodies_key(
    tables: KinematicTables,
    body_id: npt.NDArray[np.int64],
    rows: npt.NDArray[np.int64],
    pairs: npt.NDArray[np.int64],
) -> npt.NDArray[np.int64]:
    """(row, first body, second body) of each candidate as one integer, the bodies' ids in
    order: equal for the geometry pairs of one pair of bodies at one configuration."""
    import numpy as np

    n = int(body_id.max()) + 1
    a, b = body_id[tables.pair_first[pairs]], body_id[tables.pair_second[pairs]]
    key: npt.NDArray[np.int64] = (rows * n + np.minimum(a, b)) * n + np.maximum(a, b)
    return key


def _starts(key: npt.NDArray[np.int64]) -> npt.NDArray[np.intp]:
    """Where each run of equal values of the sorted ``key`` starts."""
    import numpy as np

    return np.flatnonzero(np.concatenate(([True], key[1:] != key[:-1])))


def deepest_first(
    spec: RobotSpec,
    tables: KinematicTables,
    body_id: npt.NDArray[np.int64],
    unique: npt.NDArray[np.float64],
    rows: npt.NDArray[np.int64],
    pairs: npt.NDArray[np.int64],
    bound: npt.NDArray[np.float64],
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.float64]]:
    """The candidates (sorted) with their depths (m), coal's signed distance capped by the
    ``bound``: a report names the deepest of a pair of bodies' geometry pairs only, so the
    geometry pairs of one pair of bodies at one configuration are measured deepest bound
    first, and one whose bound is no deeper than a depth already found is not measured
    (its depth is left at -inf: it cannot be the deepest).

    coal's EPA can overshoot on flat-capped cylinders (a 12.4 mm sphere-in-cylinder
    penetration read as 29 mm); the projected-overlap bound is a true upper bound."""
    import numpy as np

    key = _bodies_key(tables, body_id, rows, pairs)
    order = np.lexsort((-bound, key))  # by pair of bodies, then deepest bound first
    rows, pairs, bound, key = rows[order], pairs[order], bound[order], key[order]
    starts = _starts(key)
    ends = np.append(starts[1:], key.shape[0])
    depth = np.full(key.shape[0], -np.inf)
    best = np.full(starts.shape[0], -np.inf)
    at, pending = starts.copy(), np.arange(starts.shape[0])
    while pending.size:  # one geometry pair of each pair of bodies still open per round
        k = at[pending]
        found = -_pinocchio.pair_signed_distances(spec, unique, rows[k], pairs[k])
        depth[k] = np.minimum(found, bound[k])
        best[pending] = np.maximum(best[pending], depth[k])
        at[pending] += 1
        pending = pending[at[pending] < ends[pending]]
        pending = pending[bound[at[pending]] > best[pending]]
    return rows, pairs, depth


def deepest_by_row(
    tables: KinematicTables,
    bodies: tuple[str, ...],
    body_id: npt.NDArray[np.int64],
    rows: npt.NDArray[np.int64],
    pairs: npt.NDArray[np.int64],
    depth: npt.NDArray[np.float64],
) -> dict[int, list[tuple[str, str, float]]]:
    """Per configuration, the deepest depth (m) of each pair of bodies, sorted by bodies; a
    pair whose two geometries count as one body is not a contact."""
    import numpy as np

    names = sorted(set(bodies))  # body_id (body_ids of bodies) indexes them
    keep = body_id[tables.pair_first[pairs]] != body_id[tables.pair_second[pairs]]
    n = len(names)
    key = _bodies_key(tables, body_id, rows[keep], pairs[keep])
    order = np.argsort(key, kind="stable")
    key, d = key[order], depth[keep][order]
    if key.shape[0] == 0:
        return {}
    starts = _starts(key)
    deepest = np.maximum.reduceat(d, starts)
    by_row: dict[int, list[tuple[str, str, float]]] = {}
    for k, dk in zip(key[starts].tolist(), deepest.tolist(), strict=True):
        row, pair = divmod(k, n * n)
        by_row.setdefault(row, []).append((names[pair // n], names[pair % n], dk))
    return by_row
