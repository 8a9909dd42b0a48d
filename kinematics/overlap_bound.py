"""Step 4 of :mod:`motiontool.kinematics.collision`: upper bounds on how deep two convex
collision shapes penetrate, vectorised over many (configuration, pair)s.

Translating two convex shapes apart by their overlap along any direction separates them, so the
penetration depth is at most the smallest overlap of their projections over any set of
directions: here the line between their centres, the 3 + 3 axes of the two shapes and their 9
cross products (for two boxes, the separating-axis theorem: the bound is the exact depth).
Numpy only.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.kinematics._pinocchio import BOX, CAPSULE, CYLINDER, KinematicTables

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["overlap_bound"]


def _support(
    tables: KinematicTables,
    geoms: npt.NDArray[np.int64],
    axes: npt.NDArray[np.float64],
    directions: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]:
    """Half extent (n, D) of each geometry along each unit direction: max over the shape of
    ``x . L`` about its centre. ``geoms`` (n,), ``axes`` (n, 3, 3) (columns = the geometry's
    axes in the world), ``directions`` (n, D, 3)."""
    import numpy as np

    proj = np.abs(directions @ axes)  # |L . axis_j|, (n, D, 3)
    shape = tables.geom_shape[geoms]
    size = tables.geom_size[geoms]
    box, capsule, cylinder = shape == BOX, shape == CAPSULE, shape == CYLINDER
    r, half = size[:, 0], size[:, 1]
    # Every term for every shape, zero where it does not apply (no masked copies): a box's
    # |L . axis| . half sizes; r for a sphere, a capsule and a mesh's bounding sphere; a
    # capsule's or cylinder's half length along L; a cylinder's radius across L.
    out: npt.NDArray[np.float64] = np.where(box | cylinder, 0.0, r)[:, None]
    out = out + (proj @ np.where(box[:, None], size, 0.0)[:, :, None])[:, :, 0]
    along = proj[:, :, 2]
    out += np.where(capsule | cylinder, half, 0.0)[:, None] * along
    if cylinder.any():
        side = np.sqrt(np.clip(1.0 - along * along, 0.0, None))
        out += np.where(cylinder, r, 0.0)[:, None] * side
    return out


def overlap_bound(
    tables: KinematicTables,
    rot: npt.NDArray[np.float64],
    centers: npt.NDArray[np.float64],
    rows: npt.NDArray[np.int64],
    pairs: npt.NDArray[np.int64],
    cutoff: float | npt.NDArray[np.float64] | None = None,
) -> npt.NDArray[np.float64]:
    """Upper bound (n,) m on the penetration depth of pair ``pairs[i]`` at configuration
    ``rows[i]``: the smallest projected overlap over 16 directions (see the module doc).

    With ``cutoff`` (m; one for all, or (n,) one each), entries whose bound over the 7 face
    directions is already below it are left at that value (still an upper bound, and below
    ``cutoff``)."""
    import numpy as np

    a = tables.pair_first[pairs]
    b = tables.pair_second[pairs]
    axes_a = rot[rows, a]  # (n, 3, 3)
    axes_b = rot[rows, b]
    d = centers[rows, b] - centers[rows, a]  # (n, 3)
    ua = np.swapaxes(axes_a, 1, 2)  # rows = axes
    ub = np.swapaxes(axes_b, 1, 2)
    bound = _projected_overlap(tables, a, b, axes_a, axes_b, d, [d[:, None, :], ua, ub])
    # The cross products only for what the 7 face directions keep above the cutoff.
    keep = np.flatnonzero(bound >= cutoff) if cutoff is not None else np.arange(bound.shape[0])
    if keep.shape[0] < bound.shape[0]:
        a, b, axes_a, axes_b, d = a[keep], b[keep], axes_a[keep], axes_b[keep], d[keep]
        ua, ub = ua[keep], ub[keep]
    x, y = ua[:, :, None, :], ub[:, None, :, :]
    cross = np.stack(
        [
            x[..., 1] * y[..., 2] - x[..., 2] * y[..., 1],
            x[..., 2] * y[..., 0] - x[..., 0] * y[..., 2],
            x[..., 0] * y[..., 1] - x[..., 1] * y[..., 0],
        ],
        axis=-1,
    ).reshape(-1, 9, 3)
    edges = _projected_overlap(tables, a, b, axes_a, axes_b, d, [cross])
    bound[keep] = np.minimum(bound[keep], edges)
    return bound


def _projected_overlap(
    tables: KinematicTables,
    a: npt.NDArray[np.int64],
    b: npt.NDArray[np.int64],
    axes_a: npt.NDArray[np.float64],
    axes_b: npt.NDArray[np.float64],
    d: npt.NDArray[np.float64],
    directions: list[npt.NDArray[np.float64]],
) -> npt.NDArray[np.float64]:
    """Smallest overlap (n,) m of the two shapes' projections on the given directions (each
    (n, k, 3), not necessarily unit; near-zero ones are skipped)."""
    import numpy as np

    dirs = np.concatenate(directions, axis=1)
    norm = np.sqrt((dirs * dirs).sum(axis=2, keepdims=True))
    usable = norm[:, :, 0] > 1e-9
    dirs = dirs / np.where(usable[:, :, None], norm, 1.0)
    extent = _support(tables, a, axes_a, dirs) + _support(tables, b, axes_b, dirs)
    overlap = extent - np.abs((dirs @ d[:, :, None])[:, :, 0])
    smallest: npt.NDArray[np.float64] = np.where(usable, overlap, np.inf).min(axis=1)
    return smallest
