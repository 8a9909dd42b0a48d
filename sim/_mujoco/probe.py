"""The self-collision probe: a copy of the scene where only the candidate pairs of robot
geometries collide, run on the robot's pose each frame."""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.sim._mujoco.api import mj
from motiontool.sim._mujoco.scene import ROBOT_CLASSES, Scene
from motiontool.sim._mujoco.topology import adjacency

if TYPE_CHECKING:
    from motiontool.sim._mujoco.api import MjData, MjModel, MjsPair, MjSpec


def self_collision_probe(
    spec: MjSpec, model: MjModel, scene: Scene
) -> tuple[MjModel, MjData] | None:
    """A copy of the scene where only candidate pairs of robot geometries collide.

    Candidates, as in :func:`motiontool.kinematics.build_model`: geometries on different robot
    bodies that are not adjacent (a body and its parent, skipping bodies without geometry such
    as the Nao's Hinge2Joint helper frames) and do not already touch at the zero pose.
    """
    mujoco = mj()

    robot_geoms = [g for g in range(model.ngeom) if scene.geom_class[g] in ROBOT_CLASSES]
    if len({int(model.geom_bodyid[g]) for g in robot_geoms}) < 2:
        return None
    probe_spec = spec.copy()
    for geom in probe_spec.geoms:
        geom.contype = 0
        geom.conaffinity = 0
    names = {g: _geom_key(model, g) for g in robot_geoms}
    # Unnamed geoms get a name so that a pair can refer to them.
    spec_geoms = list(probe_spec.geoms)
    for g in robot_geoms:
        if not spec_geoms[g].name:
            spec_geoms[g].name = names[g]
    adjacent = adjacency(model, {int(model.geom_bodyid[g]) for g in robot_geoms})
    pairs = []
    for i, ga in enumerate(robot_geoms):
        for gb in robot_geoms[i + 1 :]:
            ba, bb = int(model.geom_bodyid[ga]), int(model.geom_bodyid[gb])
            if ba != bb and not adjacent(ba, bb):
                pairs.append(probe_spec.add_pair(geomname1=names[ga], geomname2=names[gb]))
    if not pairs or not _drop_touching_pairs(probe_spec, pairs):
        return None
    probe = probe_spec.compile()
    return probe, mujoco.MjData(probe)


def _drop_touching_pairs(probe_spec: MjSpec, pairs: list[MjsPair]) -> int:
    """Delete the ``pairs`` of ``probe_spec`` that already touch at the zero pose (part of the
    design); the number kept."""
    mujoco = mj()
    probe = probe_spec.compile()
    probe_data = mujoco.MjData(probe)
    mujoco.mj_kinematics(probe, probe_data)
    mujoco.mj_collision(probe, probe_data)
    touching = {
        tuple(sorted((int(a), int(b)))) for a, b in probe_data.contact.geom[: probe_data.ncon]
    }
    kept = 0
    for pair, (name_a, name_b) in zip(
        pairs, [(p.geomname1, p.geomname2) for p in pairs], strict=True
    ):
        key = tuple(sorted((probe.geom(name_a).id, probe.geom(name_b).id)))
        if key in touching:
            probe_spec.delete(pair)
        else:
            kept += 1
    return kept


def _geom_key(model: MjModel, g: int) -> str:
    name = str(model.geom(g).name)
    return name or f"motiontool_geom_{g}"
