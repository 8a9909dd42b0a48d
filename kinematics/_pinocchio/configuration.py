"""Motor positions to Pinocchio configuration vectors, and forward kinematics of one pose."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.kinematics._pinocchio.api import Model, pin_module
from motiontool.kinematics._pinocchio.model import built
from motiontool.kinematics.robots import RobotSpec, unknown_joint_message

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["body_positions", "configuration", "configurations"]


def configuration(
    model: Model, spec: RobotSpec, q_by_joint: Mapping[str, float]
) -> npt.NDArray[np.float64]:
    """Pinocchio configuration vector, shape (nq,) float64, for the named motor positions."""
    pin = pin_module()
    q = pin.neutral(model)
    for name, value in q_by_joint.items():
        jid = model.getJointId(name)
        if jid >= model.njoints or name not in spec:
            raise MotionToolError(unknown_joint_message(name, spec))
        value = float(value)
        if not math.isfinite(value):
            raise MotionToolError(f"joint '{name}' of robot {spec.name}: {value} is not a position")
        joint = model.joints[jid]
        if joint.nq == 2:
            q[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
        else:
            q[joint.idx_q] = value
    return q


def body_positions(
    spec: RobotSpec, q_by_joint: Mapping[str, float]
) -> dict[str, npt.NDArray[np.float64]]:
    """World position (m, shape (3,) float64) of every body frame at the given pose."""
    pin = pin_module()
    loaded = built(spec)
    model = loaded.model
    data, _geom_data = loaded.buffers()
    pin.framesForwardKinematics(model, data, configuration(model, spec, q_by_joint))
    return {
        frame.name: data.oMf[fid].translation.copy()
        for fid, frame in enumerate(model.frames)
        if frame.type == pin.FrameType.BODY
    }


def configurations(spec: RobotSpec, q_motors: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Pinocchio configuration vectors, shape (N, nq) float64, for motor positions
    ``q_motors`` (N, M) float64 in ``spec.joints`` order (rad or m, finite)."""
    import numpy as np

    pin = pin_module()
    model = built(spec).model
    q = np.tile(np.asarray(pin.neutral(model), dtype=np.float64), (q_motors.shape[0], 1))
    for m, joint_spec in enumerate(spec.joints):
        jid = model.getJointId(joint_spec.name)
        if jid >= model.njoints:
            raise MotionToolError(unknown_joint_message(joint_spec.name, spec))
        joint = model.joints[jid]
        if joint.nq == 2:
            q[:, joint.idx_q] = np.cos(q_motors[:, m])
            q[:, joint.idx_q + 1] = np.sin(q_motors[:, m])
        else:
            q[:, joint.idx_q] = q_motors[:, m]
    return q
