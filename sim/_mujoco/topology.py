"""The robot's tree in a compiled model: which bodies are the robot's, the limb of each body
and motor, the end effector of a fixed-base robot, which bodies are adjacent."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from motiontool.sim._mujoco.scene import TOOL_SITE_PATTERN

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.sim._mujoco.api import MjModel


def in_subtree(model: MjModel, body: int, roots: set[int]) -> bool:
    while body != 0:
        if body in roots:
            return True
        body = int(model.body_parentid[body])
    return False


def limbs(
    model: MjModel, motors: Sequence[str], root: int, bodies: npt.NDArray[np.intp]
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(limb of each motor, limb of each robot body): :func:`motiontool.kinematics.limbs.limb_of`
    by name; a motor whose name does not say takes the branch of the tree it hangs on (the
    root's child body), or ``arm`` when every motor hangs on one branch (a serial arm)."""
    from motiontool.kinematics.limbs import limb_of

    def top(body: int) -> int:
        while body != 0 and int(model.body_parentid[body]) != root and body != root:
            body = int(model.body_parentid[body])
        return body

    def generic(body: int) -> str:
        if body == root or body == 0:
            return str(model.body(root).name)
        return str(model.body(top(body)).name).removesuffix("_virtual")

    branches = {top(int(model.jnt_bodyid[model.joint(n).id])) for n in motors}

    def limb_of_joint(name: str) -> str:
        if len(branches) == 1:
            return limb_of(name, "arm")
        return limb_of(name, generic(int(model.jnt_bodyid[model.joint(name).id])))

    joint_limbs = tuple(limb_of_joint(n) for n in motors)
    body_limb: dict[int, str] = {}
    for name, limb in zip(motors, joint_limbs, strict=True):
        body_limb.setdefault(int(model.jnt_bodyid[model.joint(name).id]), limb)
    out = []
    for b in bodies.tolist():
        body = b
        while body not in body_limb and body != root and body != 0:
            body = int(model.body_parentid[body])
        out.append(body_limb.get(body, generic(b) if body != root else str(model.body(root).name)))
    return joint_limbs, tuple(out)


def tool_frame(
    model: MjModel, root: int, bodies: npt.NDArray[np.intp]
) -> tuple[str, str, int] | None:
    """The end effector of a fixed-base robot (see :class:`Scene`)."""
    in_robot = set(bodies.tolist())

    def depth(body: int) -> int:
        n = 0
        while body != 0:
            body, n = int(model.body_parentid[body]), n + 1
        return n

    sites = [
        s
        for s in range(model.nsite)
        if int(model.site_bodyid[s]) in in_robot and TOOL_SITE_PATTERN.search(model.site(s).name)
    ]
    if sites:
        site = max(sites, key=lambda s: (depth(int(model.site_bodyid[s])), -s))
        return str(model.site(site).name), "site", site
    if root not in in_robot:
        return None
    body = root
    while True:
        children = [b for b in in_robot if int(model.body_parentid[b]) == body]
        if len(children) != 1:
            return str(model.body(body).name), "body", body
        body = children[0]


def link_tree(
    model: MjModel, bodies: npt.NDArray[np.intp], floating: bool
) -> tuple[tuple[int, ...], tuple[bool, ...]]:
    """The robot's bodies as a tree of links, for ROS's ``/tf``: for each body of ``bodies``
    (in that order), the index in ``bodies`` of its parent body (-1: it hangs from the world,
    or from a scene body such as the UR5e's box, which stands still), and whether it moves
    against its parent (a joint between them; the root of a ``floating`` robot)."""
    index = {int(b): i for i, b in enumerate(bodies.tolist())}
    parents = tuple(index.get(int(model.body_parentid[b]), -1) for b in bodies.tolist())
    moving = tuple(
        int(model.body_jntnum[b]) > 0 or (floating and parent < 0)
        for b, parent in zip(bodies.tolist(), parents, strict=True)
    )
    return parents, moving


def adjacency(model: MjModel, with_geometry: set[int]) -> Callable[[int, int], bool]:
    """Whether two bodies are adjacent: one is the other's parent, bodies without geometry
    (``with_geometry`` has the others) skipped."""

    def adjacent(a: int, b: int) -> bool:
        for child, parent in ((a, b), (b, a)):
            body = child
            while body != 0:
                body = int(model.body_parentid[body])
                if body == parent:
                    return True
                if body in with_geometry:
                    break
        return False

    return adjacent
