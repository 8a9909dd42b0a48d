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
    r = size[:, 0][:, None]
    half = size[:, 1][:, None]
    out = np.repeat(r, directions.shape[1], axis=1)  # spheres; bounding spheres of meshes
    box = shape == BOX
    if box.any():
        out[box] = (proj[box] @ size[box][:, :, None])[:, :, 0]
    for code in (CAPSULE, CYLINDER):
        sel = shape == code
        if sel.any():
            along = proj[sel, :, 2]
            if code == CAPSULE:
                out[sel] = r[sel] + half[sel] * along
            else:
                side = np.sqrt(np.clip(1.0 - along * along, 0.0, None))
                out[sel] = half[sel] * along + r[sel] * side
    return out


def overlap_bound(
    tables: KinematicTables,
    rot: npt.NDArray[np.float64],
    centers: npt.NDArray[np.float64],
    rows: npt.NDArray[np.int64],
    pairs: npt.NDArray[np.int64],
    cutoff: float | None = None,
) -> npt.NDArray[np.float64]:
    """Upper bound (n,) m on the penetration depth of pair ``pairs[i]`` at configuration
    ``rows[i]``: the smallest projected overlap over 16 directions (see the module doc).

    With ``cutoff`` (m), entries whose bound over the 7 face directions is already below it
    are left at that value (still an upper bound, and below ``cutoff``)."""
    import numpy as np

    a = tables.pair_first[pairs]
    b = tables.pair_second[pairs]
    axes_a = rot[rows, a]  # (n, 3, 3)
    axes_b = rot[rows, b]
    d = centers[rows, b] - centers[rows, a]  # (n, 3)
    ua = np.swapaxes(axes_a, 1, 2)  # rows = axes
    ub = np.swapaxes(axes_b, 1, 2)
    faces = _projected_overlap(tables, a, b, axes_a, axes_b, d, [d[:, None, :], ua, ub])
    if cutoff is not None:  # the cross products only for what the 7 face axes keep
        keep = faces >= cutoff
        if not keep.all():
            out = faces.copy()
            if keep.any():
                sub = overlap_bound(tables, rot, centers, rows[keep], pairs[keep])
                out[keep] = sub
            return out
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
    bound: npt.NDArray[np.float64] = np.minimum(faces, edges)
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
