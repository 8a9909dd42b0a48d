"""Self-collision of many configurations at once.

Checking every keyframe and segment midpoint of a motion one configuration at a time through
Pinocchio costs about 0.2 ms per configuration (1479 geometry pairs on the Nao), most of it on
pairs that are far apart. Here the configurations of a whole motion are handled together:

1. identical configurations are checked once (:mod:`motiontool.kinematics.distinct_rows`),
   and a configuration met in an earlier block of the motion is not checked again;
2. a pair whose two geometries are not moved relative to each other by any motor the motion
   moves keeps its zero-pose placement, where no checked pair touches (see
   :func:`motiontool.kinematics.build_model`), and a pair of joints that no configuration of
   a block of consecutive ones can bring near (a bound on how far the motors move them,
   :mod:`motiontool.kinematics.sweep_bound`) is skipped for that block;
3. forward kinematics of the configurations left runs in numpy
   (:mod:`motiontool.kinematics.batched_kinematics`: one vectorised step per joint, a block
   of configurations at a time, the blocks side by side on the machine's cores), and a
   sphere around each joint's geometries drops the far (configuration, joint pair)s, then a
   sphere around each geometry the far (configuration, geometry pair)s;
4. two bounds on the penetration depth, both vectorised, drop every (configuration, pair)
   that cannot penetrate as deep as the tolerance. Translating two convex shapes apart by
   their overlap along any direction separates them, so the depth is at most the smallest
   projected overlap over any set of directions: first along the line between the centres of
   bounding spheres (the sphere test), then, for what is left, along the line between the
   centres, the 3 + 3 axes of the two shapes and their 9 cross products (for two boxes this
   is the separating-axis theorem, and the bound is the exact depth;
   :mod:`motiontool.kinematics.overlap_bound`); in between, a pair of geometries is dropped
   for a run of consecutive configurations where its bound at the run's first one, plus how
   far its geometries move in the run, stays below the tolerance
   (:mod:`motiontool.kinematics.pair_sweep`);
5. only the remaining candidates go to coal (GJK/EPA signed distance, through Pinocchio), the
   deepest bound of each pair of bodies first: a geometry pair whose bound is no deeper than
   the depth already found for its bodies is not measured
   (:mod:`motiontool.kinematics.contact_depth`).

Pinocchio is imported (lazily) by :mod:`motiontool.kinematics._pinocchio` only, and only
when step 5 has candidates: the tables of steps 1-4 come from the disk cache
(:mod:`motiontool.kinematics.tables_cache`) once they have been built.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, NamedTuple

from motiontool.errors import MotionToolError
from motiontool.kinematics import _pinocchio
from motiontool.kinematics._pinocchio import KinematicTables
from motiontool.kinematics.batched_kinematics import (
    forward_kinematics,
    geometry_centers,
    geometry_poses,
    joint_first,
)
from motiontool.kinematics.contact_depth import body_ids, deepest_by_row, deepest_first
from motiontool.kinematics.distinct_rows import Known, distinct_rows
from motiontool.kinematics.overlap_bound import overlap_bound
from motiontool.kinematics.pair_sweep import uncleared
from motiontool.kinematics.robots import RobotSpec
from motiontool.kinematics.sweep_bound import SWEEP_BLOCK, cleared_groups
from motiontool.kinematics.tables_cache import stored_tables
from motiontool.motionfmt.arrays import sorted_distinct

if TYPE_CHECKING:
    from collections.abc import Callable

    import numpy as np
    import numpy.typing as npt

    _Candidates = tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.float64]]
    """(configuration rows, pair indices, upper bounds on the depth in m), one entry each."""

__all__ = [
    "Contact",
    "Known",
    "body_joints",
    "forward_kinematics",
    "geometry_centers",
    "geometry_poses",
    "scan_self_collisions",
]


class Contact(NamedTuple):
    """Two bodies in collision at one configuration.

    Attributes:
        config: row of the configuration in the array that was scanned.
        body_a: the body (MJCF) or link (URDF) holding the first geometry; ``body_a < body_b``.
        body_b: the other body.
        depth_m: penetration depth, m (> 0): the deepest over the two bodies' geometry pairs.
    """

    config: int
    body_a: str
    body_b: str
    depth_m: float


def _joint_broad_phase(
    tables: KinematicTables,
    fk: tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]],
    active: npt.NDArray[np.int64],
    tolerance: float,
    open_rows: npt.NDArray[np.bool_] | None = None,
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """(configuration rows, pair indices) of the ``active`` pairs whose two joints' enclosing
    spheres overlap by at least ``tolerance`` (m) at that configuration, by pair group then
    configuration; only groups that ``open_rows`` ((N, groups) bool, if given) leaves open at
    the configuration."""
    import numpy as np

    rot, pos = joint_first(fk)
    n = rot.shape[1]
    groups = sorted_distinct(tables.pair_group[active])
    ja, jb = tables.group_joints[groups, 0], tables.group_joints[groups, 1]
    used = sorted_distinct(np.concatenate([ja, jb]))
    slot = np.zeros(tables.joint_parent.shape[0], dtype=np.int64)
    slot[used] = np.arange(used.shape[0])
    xyz = np.empty((3, used.shape[0], n))  # a row per joint used: gathers copy whole rows
    for k, j in enumerate(used.tolist()):
        xyz[:, k] = (pos[j] + (rot[j].reshape(3 * n, 3) @ tables.joint_center[j]).reshape(n, 3)).T
    sa, sb = slot[ja], slot[jb]
    gap2 = np.zeros((groups.shape[0], n))
    for x in xyz:
        d = x[sa]
        d -= x[sb]
        d *= d
        gap2 += d
    limit = tables.joint_radius[ja] + tables.joint_radius[jb] - tolerance
    near = (gap2 <= (limit * limit)[:, None]) & (limit >= 0.0)[:, None]
    if open_rows is not None:
        near &= open_rows[:, groups].T
    cols_g, rows_g = np.nonzero(near)  # (group, configuration) candidates
    # Expand each candidate group into its active pairs (CSR over the groups).
    order = np.argsort(tables.pair_group[active], kind="stable")
    by_group = active[order]
    starts = np.searchsorted(tables.pair_group[by_group], groups)
    counts = np.searchsorted(tables.pair_group[by_group], groups, side="right") - starts
    count = counts[cols_g]
    rows = np.repeat(rows_g, count)
    offsets = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    pairs = by_group[np.repeat(starts[cols_g], count) + offsets]
    return rows, pairs


#: Configurations handled at once (bounds the memory of the batched kinematics: ~0.5 GB for
#: 16 384 Nao configurations, ~30 MB for this many).
_BLOCK = 1024
#: Blocks handled side by side at most (each holds its ~30 MB; more cores do not add memory).
_THREADS = 4


def _candidates(
    spec: RobotSpec,
    tables: KinematicTables,
    unique: npt.NDArray[np.float64],
    active: npt.NDArray[np.int64],
    tolerance: float,
    open_groups: npt.NDArray[np.bool_] | None = None,
) -> _Candidates:
    """(rows of ``unique``, pair indices, depth upper bounds in m) of the (configuration,
    pair)s that may penetrate at least ``tolerance`` m deep (see the module doc).
    ``open_groups``: the pair groups that each row's block of consecutive rows may bring
    near ((rows, groups) bool, :func:`~motiontool.kinematics.sweep_bound.cleared_groups`):
    the others are not looked at, and rows with none open not evaluated."""
    import numpy as np

    if open_groups is None:
        return _near_pairs(spec, tables, unique, active, tolerance)
    open_anywhere = np.asarray(open_groups.any(axis=0))
    active = active[open_anywhere[tables.pair_group[active]]]
    at = np.flatnonzero(open_groups.any(axis=1))
    if active.size == 0 or at.size == 0:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty, np.zeros(0)
    rows, pairs, bound = _near_pairs(spec, tables, unique[at], active, tolerance, open_groups[at])
    return at[rows], pairs, bound


def _near_pairs(
    spec: RobotSpec,
    tables: KinematicTables,
    unique: npt.NDArray[np.float64],
    active: npt.NDArray[np.int64],
    tolerance: float,
    open_rows: npt.NDArray[np.bool_] | None = None,
) -> _Candidates:
    """:func:`_candidates` of every row of ``unique``, each looking at the groups its row of
    ``open_rows`` leaves open (all, if None)."""
    import numpy as np

    reach = tables.geom_radius[tables.pair_first] + tables.geom_radius[tables.pair_second]
    rot = None
    if tables.exact:
        fk = forward_kinematics(tables, unique)
        rot, centers = geometry_poses(tables, unique, fk)
        rows, pairs = _joint_broad_phase(tables, fk, active, tolerance, open_rows)
    else:
        centers = _pinocchio.geometry_centers(spec, unique)
        rows = np.repeat(np.arange(unique.shape[0]), active.shape[0])
        pairs = np.tile(active, unique.shape[0])
    limit = reach[pairs] - tolerance
    gap2 = _squared_gaps(centers, rows, tables.pair_first[pairs], tables.pair_second[pairs])
    near = gap2 <= limit * limit  # bounding spheres of the geometries
    rows, pairs = rows[near], pairs[near]
    if rot is not None:
        rows, pairs = uncleared(tables, unique, rot, centers, rows, pairs, tolerance)
    bound = np.full(rows.shape[0], np.inf)
    if rot is not None and rows.size:
        bound = overlap_bound(tables, rot, centers, rows, pairs, cutoff=tolerance)
        tight = bound >= tolerance
        rows, pairs, bound = rows[tight], pairs[tight], bound[tight]
    return rows, pairs, bound


def _squared_gaps(
    centers: npt.NDArray[np.float64],
    rows: npt.NDArray[np.int64],
    first: npt.NDArray[np.int64],
    second: npt.NDArray[np.int64],
) -> npt.NDArray[np.float64]:
    """(C,) m²: squared distance of geometry ``first[i]``'s centre from ``second[i]``'s at
    configuration ``rows[i]``, of ``centers`` (N, G, 3), m; a coordinate at a time (gathers of
    single numbers from one contiguous plane are several times faster than of (3,) rows)."""
    import numpy as np

    n = centers.shape[0]
    planes = np.ascontiguousarray(centers.transpose(2, 1, 0)).reshape(3, -1)  # (3, G * N)
    at_first, at_second = first * n + rows, second * n + rows
    gap2 = np.zeros(rows.shape[0])
    for plane in planes:
        d = plane[at_first]
        d -= plane[at_second]
        d *= d
        gap2 += d
    return gap2


KNOWN_CONFIGURATIONS = 1 << 15
"""The most configurations a ``known`` memo of :func:`scan_self_collisions` keeps (about 15 MB
for the Nao): the first ones met, which a long motion that repeats a cycle meets again."""


def scan_self_collisions(
    spec: RobotSpec,
    q_motors: npt.ArrayLike,
    *,
    penetration_tolerance_m: float = 0.0,
    fingers_in_hand: bool = False,
    known: Known | None = None,
) -> list[Contact]:
    """Every pair of bodies in collision, at each of N configurations.

    Args:
        spec: the robot.
        q_motors: (N, M) motor positions in ``spec.joints`` order, rad or m, finite.
        penetration_tolerance_m: report only contacts at least this deep, m (0: every
            intersection).
        fingers_in_hand: name a finger by its hand (``r_phalanx4`` counts as ``r_hand``), so
            that a hand with its fingers in contact is one contact; a finger touching its own
            hand is then not reported.
        known: a memo shared by calls with the same robot and options (a motion scanned a
            block of configurations at a time): the contacts of configurations already
            scanned, by their hash and bytes; the first :data:`KNOWN_CONFIGURATIONS` are
            added to it.

    Returns:
        One :class:`Contact` per configuration and pair of bodies, sorted by configuration
        then bodies. The same pairs as :func:`motiontool.kinematics.self_collision_depths`
        (adjacent bodies and pairs touching at the zero pose are never reported).

    Raises:
        MotionToolError: ``q_motors`` has the wrong shape or a value that is not finite.
    """
    import numpy as np

    q = _checked(spec, q_motors)
    if q.shape[0] == 0:
        return []
    unique, inverse, hashed = distinct_rows(q)
    memo = Known() if known is None else known
    rows, at_row = memo.split(unique, hashed)
    fresh = unique if rows.shape[0] == unique.shape[0] else unique[rows]  # none met before
    found = _scan_unique(spec, fresh, penetration_tolerance_m, fingers_in_hand)
    for n, row_contacts in found.items():
        at_row[int(rows[n])] = tuple(row_contacts)
    for i in rows[: max(KNOWN_CONFIGURATIONS - len(memo), 0)].tolist():  # the first met
        memo.remember(int(hashed[i]), unique[i].tobytes(), at_row.get(i, ()))
    touching = np.zeros(unique.shape[0], dtype=bool)
    touching[list(at_row)] = True
    touching = touching[inverse]
    contacts: list[Contact] = []
    for config, row in zip(
        np.flatnonzero(touching).tolist(), inverse[touching].tolist(), strict=True
    ):
        contacts.extend(Contact(config, a, b, d) for a, b, d in at_row[row])
    return contacts


def body_joints(spec: RobotSpec, *, fingers_in_hand: bool = True) -> dict[str, str | None]:
    """The motor (a name of ``spec.joints``) that carries each body a :class:`Contact` can
    name: of the motors its geometries hang from, the one nearest the root (a hand's wrist, not
    its fingers); None for a body no motor moves (the root, e.g. the Nao's torso). Bodies are
    named as :func:`scan_self_collisions` names them with ``fingers_in_hand``."""
    tables = stored_tables(spec)
    bodies = tables.geom_limb if fingers_in_hand else tables.geom_body
    carrier: dict[str, int] = {}
    for g, body in enumerate(bodies):
        j = int(tables.geom_joint[g])
        while j > 0 and tables.joint_motor[j] < 0:  # up through fixed joints to a motor
            j = int(tables.joint_parent[j])
        carrier[body] = min(carrier.get(body, j), j)  # a parent comes before its children
    return {
        body: spec.joints[int(tables.joint_motor[j])].name if j > 0 else None
        for body, j in carrier.items()
    }


def _scan_unique(
    spec: RobotSpec, unique: npt.NDArray[np.float64], tolerance_m: float, fingers_in_hand: bool
) -> dict[int, list[tuple[str, str, float]]]:
    """The contacts (body_a, body_b, depth m) at each of the distinct configurations
    ``unique``, by row (rows without one left out); see :func:`scan_self_collisions`."""
    import numpy as np

    if unique.shape[0] == 0:
        return {}
    tables = stored_tables(spec)
    moving = (unique != 0.0).any(axis=0)
    tolerance = max(tolerance_m, 0.0)
    reach = tables.geom_radius[tables.pair_first] + tables.geom_radius[tables.pair_second]
    bodies = tables.geom_limb if fingers_in_hand else tables.geom_body
    body_id = body_ids(bodies)
    apart = body_id[tables.pair_first] != body_id[tables.pair_second]  # one body: no contact
    active = np.flatnonzero(
        tables.pair_motors[:, moving].any(axis=1) & (reach >= tolerance) & apart
    )
    if active.size == 0:
        return {}

    groups = sorted_distinct(tables.pair_group[active])
    cleared = cleared_groups(tables, unique, groups, tolerance)
    open_blocks = None
    if cleared is not None:
        open_blocks = np.zeros((cleared.shape[0], tables.group_joints.shape[0]), dtype=bool)
        open_blocks[:, groups] = ~cleared
    rows, pairs, bound = _in_blocks(
        lambda k: _candidates(
            spec,
            tables,
            unique[k : k + _BLOCK],
            active,
            tolerance,
            None if open_blocks is None else open_blocks[_sweep_blocks(k, unique.shape[0])],
        ),
        unique.shape[0],
    )
    if rows.size == 0:
        return {}
    rows, pairs, depth = deepest_first(spec, tables, body_id, unique, rows, pairs, bound)
    hit = (depth > 0.0) & (depth >= tolerance_m)
    return deepest_by_row(tables, bodies, body_id, rows[hit], pairs[hit], depth[hit])


def _sweep_blocks(start: int, n: int) -> npt.NDArray[np.int64]:
    """The block of :data:`SWEEP_BLOCK` rows of each of the :data:`_BLOCK` rows from
    ``start`` (fewer at the end of ``n`` rows)."""
    import numpy as np

    return np.arange(start, min(start + _BLOCK, n)) // SWEEP_BLOCK


def _in_blocks(block: Callable[[int], _Candidates], n: int) -> _Candidates:
    """``block(start)`` (:func:`_candidates` of the :data:`_BLOCK` configurations from
    ``start``) of every block of ``n`` configurations, their rows counted from the first:
    numpy lets go of the GIL in its loops, so the blocks run side by side on the machine's
    cores."""
    import numpy as np

    starts = range(0, n, _BLOCK)
    if len(starts) == 1:  # one block: no thread to start
        blocks = [block(0)]
    else:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(max_workers=min(_THREADS, os.cpu_count() or 1)) as pool:
            blocks = list(pool.map(block, starts))
    rows = np.concatenate([r + k for k, (r, _p, _b) in zip(starts, blocks, strict=True)])
    pairs = np.concatenate([p for _r, p, _b in blocks])
    bound = np.concatenate([b for _r, _p, b in blocks])
    return rows, pairs, bound


def _checked(spec: RobotSpec, q_motors: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """``q_motors`` as an (N, M) float64 array, or an error naming the expected shape."""
    import numpy as np

    q = np.asarray(q_motors, dtype=np.float64)
    if q.ndim != 2 or q.shape[1] != len(spec.joints):
        raise MotionToolError(
            f"robot {spec.name}: expected configurations of shape (N, {len(spec.joints)}), "
            f"got {q.shape}"
        )
    if not np.isfinite(q).all():
        raise MotionToolError(f"robot {spec.name}: a configuration holds a non-finite value")
    return q
