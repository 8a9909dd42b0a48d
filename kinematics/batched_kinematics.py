"""Forward kinematics of N configurations at once, in numpy: step 3 of
:mod:`motiontool.kinematics.collision`.

Each model joint frame is one vectorised step over all configurations (a joint's N rotations
are one (3N, 3) matrix), from the tables of
:func:`motiontool.kinematics._pinocchio.kinematic_tables`: no Pinocchio call. Rotations are
3 x 3, translations and centres in m, motor positions in rad (revolute) or m (prismatic).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.kinematics._pinocchio import PRISMATIC, REVOLUTE, KinematicTables

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["forward_kinematics", "geometry_centers", "geometry_poses", "joint_first"]


def _skew(axis: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The matrix K (3, 3) of ``axis x v``: a rotation by θ about the unit ``axis`` is
    I + sin θ K + (1 - cos θ) K² (Rodrigues)."""
    import numpy as np

    x, y, z = axis
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _joint_frames(
    tables: KinematicTables, q_motors: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """:func:`forward_kinematics`, joint first: rotations (nj, N, 3, 3) and translations
    (nj, N, 3). A joint's N frames are one (3N, 3) matrix, so each step is one matrix product
    with a constant (the joint's placement, K, K²) and a per-configuration scaling."""
    import numpy as np

    n = q_motors.shape[0]
    nj = tables.joint_parent.shape[0]
    moving = np.append((q_motors != 0.0).any(axis=0), False)  # index -1: no motor
    rot = np.empty((nj, n, 3, 3))
    pos = np.empty((nj, n, 3))
    rot[0] = np.eye(3)
    pos[0] = 0.0
    for j in range(1, nj):
        parent = int(tables.joint_parent[j])
        r_parent = rot[parent].reshape(3 * n, 3)
        r_j = rot[j].reshape(3 * n, 3)
        np.matmul(r_parent, tables.joint_rotation[j], out=r_j)
        np.add(pos[parent], (r_parent @ tables.joint_translation[j]).reshape(n, 3), out=pos[j])
        kind, motor = tables.joint_kind[j], tables.joint_motor[j]
        if kind != PRISMATIC and not moving[motor]:
            continue  # a motor held at 0 for every configuration: identity motion
        q = q_motors[:, motor]
        if kind == REVOLUTE:
            k = _skew(tables.joint_axis[j])
            r_k, r_kk = (r_j @ k).reshape(n, 3, 3), (r_j @ (k @ k)).reshape(n, 3, 3)
            rot[j] += np.sin(q)[:, None, None] * r_k
            rot[j] += (1.0 - np.cos(q))[:, None, None] * r_kk
        elif kind == PRISMATIC:
            pos[j] += (r_j @ tables.joint_axis[j]).reshape(n, 3) * q[:, None]
    return rot, pos


def forward_kinematics(
    tables: KinematicTables, q_motors: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """World placement of every model joint frame for N configurations at once.

    Args:
        tables: the model (:func:`motiontool.kinematics._pinocchio.kinematic_tables`).
        q_motors: (N, M) float64, motor positions in ``spec.joints`` order, rad or m.

    Returns:
        (rotations (N, nj, 3, 3), translations (N, nj, 3) in m), float64 (views of joint-first
        arrays); a free-flying root stays at the origin, upright.
    """
    rot, pos = _joint_frames(tables, q_motors)
    return rot.transpose(1, 0, 2, 3), pos.transpose(1, 0, 2)


def geometry_poses(
    tables: KinematicTables,
    q_motors: npt.NDArray[np.float64],
    fk: tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]] | None = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """World orientation (N, G, 3, 3) and bounding-sphere centre (N, G, 3), m, of every
    collision geometry, float64 (the centre is the geometry's origin for primitives).
    ``fk``: the result of :func:`forward_kinematics` for ``q_motors``, if already computed."""
    import numpy as np

    rot, pos = _joint_frames(tables, q_motors) if fk is None else joint_first(fk)
    n = rot.shape[1]
    local = tables.geom_translation + np.einsum(
        "gij,gj->gi", tables.geom_rotation, tables.geom_center
    )
    count = tables.geom_joint.shape[0]
    out_rot = np.empty((count, n, 3, 3))
    out_center = np.empty((count, n, 3))
    for g, j in enumerate(tables.geom_joint.tolist()):
        r_joint = rot[j].reshape(3 * n, 3)
        np.matmul(r_joint, tables.geom_rotation[g], out=out_rot[g].reshape(3 * n, 3))
        np.add(pos[j], (r_joint @ local[g]).reshape(n, 3), out=out_center[g])
    return out_rot.transpose(1, 0, 2, 3), out_center.transpose(1, 0, 2)


def joint_first(
    fk: tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """:func:`forward_kinematics`' result as :func:`_joint_frames` gives it (its own arrays,
    where it is a view of them)."""
    import numpy as np

    rot, pos = fk
    return np.ascontiguousarray(rot.transpose(1, 0, 2, 3)), np.ascontiguousarray(
        pos.transpose(1, 0, 2)
    )


def geometry_centers(
    tables: KinematicTables, q_motors: npt.NDArray[np.float64]
) -> npt.NDArray[np.float64]:
    """World centres (N, G, 3) float64, m, of the geometries' bounding spheres."""
    return geometry_poses(tables, q_motors)[1]
