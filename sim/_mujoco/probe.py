"""Self-collision, by Webots' rule for ``selfCollision``: which pairs of robot geometries can
collide (:func:`self_collision_pairs`), the probe that detects them each frame
(:func:`self_collision_probe`: a copy of the scene where only those pairs collide, run on the
robot's pose) and self-collision physics (:func:`collide_self`: the robot's parts collide with
each other in the simulation itself)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from motiontool.sim._mujoco.api import mj
from motiontool.sim._mujoco.scene import ROBOT_CLASSES, Scene
from motiontool.sim._mujoco.topology import adjacency

if TYPE_CHECKING:
    from motiontool.sim._mujoco.api import MjData, MjModel, MjSpec

GeomPair = tuple[int, int]
"""Two geom ids of a compiled scene, the smaller first."""

ROBOT_CONTYPE = 1
"""``contype`` bit of a robot geometry by which it collides with the floor and the scene (their
``conaffinity`` is 1)."""

ROBOT_BIT = 2
"""``contype`` and ``conaffinity`` bit by which robot geometries collide with each other
(self-collision physics on)."""


def self_collision_pairs(spec: MjSpec, model: MjModel, scene: Scene) -> list[GeomPair]:
    """The pairs of robot geometries that can collide, by Webots' rule for ``selfCollision``
    (Robot node reference: only collisions between non-consecutive solids; none between two
    solids attached to each other by a joint, nor along a chain whose joints share an anchor).

    Candidates, as in :func:`motiontool.kinematics.build_model`: geometries on different robot
    bodies that are not adjacent (a body and its parent, skipping bodies without geometry such
    as the Nao's Hinge2Joint helper frames, whose joints share the anchor) and do not already
    touch at the zero pose (part of the design: the bounding primitives of Webots' robots).
    """
    robot_geoms = [g for g in range(model.ngeom) if scene.geom_class[g] in ROBOT_CLASSES]
    adjacent = adjacency(model, {int(model.geom_bodyid[g]) for g in robot_geoms})
    candidates = []
    for i, ga in enumerate(robot_geoms):
        for gb in robot_geoms[i + 1 :]:
            ba, bb = int(model.geom_bodyid[ga]), int(model.geom_bodyid[gb])
            if ba != bb and not adjacent(ba, bb):
                candidates.append((ga, gb))
    if not candidates:
        return []
    mujoco = mj()
    probe = _pairs_only(spec, model, candidates).compile()
    data = mujoco.MjData(probe)
    mujoco.mj_kinematics(probe, data)
    mujoco.mj_collision(probe, data)
    touching = {tuple(sorted((int(a), int(b)))) for a, b in data.contact.geom[: data.ncon]}
    return [p for p in candidates if p not in touching]


def self_collision_probe(
    spec: MjSpec, model: MjModel, pairs: Sequence[GeomPair]
) -> tuple[MjModel, MjData] | None:
    """A copy of the scene where only ``pairs`` collide (None: no pair)."""
    if not pairs:
        return None
    probe = _pairs_only(spec, model, pairs).compile()
    return probe, mj().MjData(probe)


def collide_self(
    spec: MjSpec, model: MjModel, scene: Scene, pairs: Sequence[GeomPair], on: bool
) -> None:
    """Turn self-collision physics on or off in ``spec`` (``model``: it compiled).

    Off, every robot geometry that collides keeps colliding with the floor and the scene but
    not with the robot (``contype`` :data:`ROBOT_CONTYPE`, ``conaffinity`` 0). On, they also
    collide with each other (the :data:`ROBOT_BIT` of both), and the pairs of bodies none of
    whose geometries are in ``pairs`` are excluded (``<contact><exclude>``, so that MuJoCo's
    broad phase skips them); a pair of bodies with some of its geometries in ``pairs`` is
    excluded and those become explicit pairs. MuJoCo's own parent-child filter is off: it
    filters by welded groups of bodies (a Nao's foot sensor with the ankle), the exclusions
    already follow the rule. Contacts have MuJoCo's defaults: friction 1 (Webots' default
    ``coulombFriction``), no bounce.
    """
    geoms = list(spec.geoms)
    colliding = [
        g
        for g in range(model.ngeom)
        if scene.geom_class[g] in ROBOT_CLASSES
        and (model.geom_contype[g] or model.geom_conaffinity[g])
    ]
    for g in colliding:
        geoms[g].contype = ROBOT_CONTYPE | (ROBOT_BIT if on else 0)
        geoms[g].conaffinity = ROBOT_BIT if on else 0
    if not on:
        return
    spec.option.disableflags |= int(mj().mjtDisableBit.mjDSBL_FILTERPARENT)
    allowed = set(pairs)
    by_bodies: dict[tuple[int, int], list[tuple[GeomPair, bool]]] = {}
    for i, a in enumerate(colliding):
        for b in colliding[i + 1 :]:
            ba, bb = int(model.geom_bodyid[a]), int(model.geom_bodyid[b])
            if ba != bb:
                key = (min(ba, bb), max(ba, bb))
                by_bodies.setdefault(key, []).append(((a, b), (a, b) in allowed))
    for (ba, bb), geom_pairs in by_bodies.items():
        if all(ok for _, ok in geom_pairs):
            continue
        spec.add_exclude(bodyname1=model.body(ba).name, bodyname2=model.body(bb).name)
        for (a, b), ok in geom_pairs:
            if ok:
                spec.add_pair(geomname1=_name(geoms, model, a), geomname2=_name(geoms, model, b))


def self_collides(model: MjModel, scene: Scene) -> bool:
    """Whether two robot geometries of different bodies can collide in ``model`` (explicit
    pairs, or ``contype``/``conaffinity``; MuJoCo's parent-child filter aside)."""
    robot = [g for g in range(model.ngeom) if scene.geom_class[g] in ROBOT_CLASSES]
    for a, b in zip(model.pair_geom1.tolist(), model.pair_geom2.tolist(), strict=True):
        if (
            model.geom_bodyid[a] != model.geom_bodyid[b]
            and scene.geom_class[a] in ROBOT_CLASSES
            and scene.geom_class[b] in ROBOT_CLASSES
        ):
            return True
    kinds = {(int(model.geom_contype[g]), int(model.geom_conaffinity[g])) for g in robot}
    bodies = len({int(model.geom_bodyid[g]) for g in robot})
    return bodies > 1 and any(t1 & a2 or t2 & a1 for t1, a1 in kinds for t2, a2 in kinds)


def _pairs_only(spec: MjSpec, model: MjModel, pairs: Sequence[GeomPair]) -> MjSpec:
    """A copy of ``spec`` where no geometry collides but ``pairs``."""
    copy = spec.copy()
    geoms = list(copy.geoms)
    for geom in geoms:
        geom.contype = 0
        geom.conaffinity = 0
    for a, b in pairs:
        copy.add_pair(geomname1=_name(geoms, model, a), geomname2=_name(geoms, model, b))
    return copy


def _name(geoms: Sequence[object], model: MjModel, g: int) -> str:
    """The name of geom ``g`` (an unnamed one gets one, so that a pair can refer to it)."""
    geom = geoms[g]
    name = str(model.geom(g).name)
    if not name:
        name = f"motiontool_geom_{g}"
        geom.name = name  # type: ignore[attr-defined]
    return name
