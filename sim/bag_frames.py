"""The robot's links as ROS's ``/tf`` wants them: each link's pose in its parent link's frame,
made from the world poses the simulation measured (MuJoCo's ``xpos`` / ``xquat`` of each body,
:attr:`motiontool.sim.trace.Trace.body_pos`), so that chaining the transforms from the world
gives back the measured pose of every link (numpy only)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.sim.trace import Trace

__all__ = ["WORLD_FRAME", "LinkTree", "transforms"]

WORLD_FRAME = "world"
"""The frame id of the world, the parent of the root link (and of anything the robot stands
on)."""


@dataclass(frozen=True)
class LinkTree:
    """The robot's links (:func:`motiontool.sim._mujoco.link_tree`).

    Attributes:
        links: the frame id of each robot body, in the order of the trace's ``bodies`` (the
            body names, which are the link names of the URDF in ``description``).
        parents: the index in ``links`` of each link's parent, -1: :data:`WORLD_FRAME`.
        moving: whether each link moves against its parent (a joint between them, or a
            free-flying root); the others are fixed (``/tf_static``).
        description: the robot's URDF text.
    """

    links: tuple[str, ...]
    parents: tuple[int, ...]
    moving: tuple[bool, ...]
    description: str

    def moving_links(self) -> list[int]:
        """The indices of the links that move against their parent."""
        return [i for i, m in enumerate(self.moving) if m]

    def fixed_links(self) -> list[int]:
        """The indices of the links fixed to their parent."""
        return [i for i, m in enumerate(self.moving) if not m]

    def parent_frame(self, link: int) -> str:
        parent = self.parents[link]
        return WORLD_FRAME if parent < 0 else self.links[parent]


Transform = tuple[str, str, Any, Any]
"""(parent frame, child frame, position (3,) m, unit quaternion (4,) w x y z)."""


def transforms(
    tree: LinkTree, chunk: Trace, links: list[int], first: int, frames: int | None = None
) -> list[list[Transform]]:
    """For each frame of ``chunk`` from ``first`` (``frames`` of them, default: to the end), the
    pose of each of ``links`` in its parent's frame.

    Raises:
        ValueError: the chunk does not carry the poses of the tree's bodies (a bug).
    """
    import numpy as np

    if chunk.bodies != tree.links or chunk.body_pos.shape[0] != len(chunk.time_s):
        raise ValueError("the chunk carries no pose of the robot's links")
    end = len(chunk.time_s) if frames is None else first + frames
    pos, quat = chunk.body_pos[first:end], chunk.body_quat[first:end]
    index = np.array(links, dtype=np.intp)
    parents = np.array([tree.parents[i] for i in links], dtype=np.intp)
    rel_pos, rel_quat = pos[:, index].copy(), quat[:, index].copy()
    inner = parents >= 0
    if inner.any():
        p_pos, p_quat = pos[:, parents[inner]], quat[:, parents[inner]]
        inverse = _conjugate(p_quat)
        rel_pos[:, inner] = _rotate(inverse, pos[:, index[inner]] - p_pos)
        rel_quat[:, inner] = _multiply(inverse, quat[:, index[inner]])
    names = [(tree.parent_frame(i), tree.links[i]) for i in links]
    return [
        [(parent, child, p, q) for (parent, child), p, q in zip(names, fp, fq, strict=True)]
        for fp, fq in zip(rel_pos, rel_quat, strict=True)
    ]


def _conjugate(q: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The inverse of unit quaternions (..., 4) w x y z."""
    out = q.copy()
    out[..., 1:] *= -1.0
    return out


def _multiply(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Hamilton products ``a * b`` of quaternions (..., 4) w x y z."""
    import numpy as np

    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        axis=-1,
    )


def _rotate(q: npt.NDArray[np.float64], v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Vectors (..., 3) rotated by unit quaternions (..., 4) w x y z."""
    import numpy as np

    w, u = q[..., :1], q[..., 1:]
    t = 2.0 * np.cross(u, v)
    rotated: npt.NDArray[np.float64] = v + w * t + np.cross(u, t)
    return rotated
