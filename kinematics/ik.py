"""Inverse kinematics: the motor positions that put a named frame at a given pose.

Damped least squares (Levenberg–Marquardt) on the SE(3) logarithm of the frame's pose error,
on the robot's Pinocchio model (:func:`motiontool.kinematics._pinocchio.build_model`):

* the residual is ``e(q) = log6(oMf(q)^-1 · oMdes)``, shape (6,), linear part (m) then
  angular part (rad), in the frame's own axes; its Jacobian is ``-Jlog6(fMdes^-1) · J_local``
  (checked against finite differences in the tests);
* a step ``dq = -(JᵀJ + λI)⁻¹ Jᵀe`` is projected onto the joint limits (each motor clamped to
  its ``[lower, upper]``) and accepted only if it lowers ``|e|²``; a motor pressed against a
  limit thus stays on it while the growing damping turns the step toward the gradient, along
  which the other motors still make progress; λ shrinks tenfold after an accepted step and
  grows tenfold after a rejected one, so the solver walks like Gauss–Newton near the solution
  and like a short gradient step far from it or near a singularity;
* the search starts from a seed configuration and moves continuously from it, so consecutive
  waypoints solved from each other's solutions stay on the same IK branch (elbow up or down,
  wrist flipped or not).

Poses are expressed in the model's world frame, i.e. the robot's base frame for a fixed-base
arm (a free-flying root, such as the Nao's torso, stays at the origin, upright). Pinocchio is
imported inside the functions only.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.kinematics._pinocchio.api import SE3, Data, Model, Pinocchio, pin_module
from motiontool.kinematics._pinocchio.configuration import configuration
from motiontool.kinematics.robots import RobotSpec, unknown_joint_message
from motiontool.motionfmt.units import MM_PER_M

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = [
    "IKSolution",
    "Pose",
    "forward_pose",
    "frame_jacobian",
    "solve_ik",
]

_log = logging.getLogger("motiontool")

#: Default convergence tolerances: 1 µm and 10 µrad (0.00057°), far below what a motor resolves.
DEFAULT_POSITION_TOLERANCE_M = 1e-6
DEFAULT_ORIENTATION_TOLERANCE_RAD = 1e-5
#: Largest change of one motor in one iteration (rad or m): keeps a step inside the region
#: where the linearisation holds.
MAX_STEP = 0.5
_LAMBDA_START = 1e-3
_LAMBDA_MIN = 1e-12
_LAMBDA_MAX = 1e8


@dataclass(frozen=True, eq=False)
class Pose:
    """A rigid placement in the model's world frame.

    Attributes:
        position: m, shape (3,) float64.
        rotation: rotation matrix, shape (3, 3) float64, whose columns are the frame's x, y and
            z axes written in world coordinates.
    """

    position: npt.NDArray[np.float64]
    rotation: npt.NDArray[np.float64]

    def __post_init__(self) -> None:
        import numpy as np

        position = np.array(self.position, dtype=np.float64).reshape(3)
        rotation = np.array(self.rotation, dtype=np.float64).reshape(3, 3)
        if not (np.all(np.isfinite(position)) and np.all(np.isfinite(rotation))):
            raise MotionToolError("a pose needs a finite position (m) and rotation")
        if not np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-9) or (
            np.linalg.det(rotation) < 0
        ):
            raise MotionToolError("a pose's rotation must be orthonormal with determinant +1")
        position.flags.writeable = False
        rotation.flags.writeable = False
        object.__setattr__(self, "position", position)
        object.__setattr__(self, "rotation", rotation)

    def errors_to(self, other: Pose) -> tuple[float, float]:
        """Distance to ``other``: position error in m and rotation angle in rad (0 to π)."""
        import numpy as np

        position = float(np.linalg.norm(other.position - self.position))
        relative = self.rotation.T @ other.rotation
        cos = (float(np.trace(relative)) - 1.0) / 2.0
        # arccos is ill-conditioned near 0: use the skew part for small angles.
        sin = float(np.linalg.norm(relative - relative.T)) / (2.0 * math.sqrt(2.0))
        return position, math.atan2(sin, max(-1.0, min(1.0, cos)))


@dataclass(frozen=True)
class IKSolution:
    """A converged inverse-kinematics solution.

    Attributes:
        q_by_joint: every motor of the robot, in model order, rad (m for slides); motors the
            solver did not move keep their seed value.
        position_error_m: remaining distance between the frame and the target, m.
        orientation_error_rad: remaining rotation angle between them, rad.
        iterations: Levenberg–Marquardt iterations used (accepted and rejected steps).
    """

    q_by_joint: Mapping[str, float]
    position_error_m: float
    orientation_error_rad: float
    iterations: int

    def values(self, joints: Sequence[str]) -> list[float]:
        """The solution's positions of ``joints``, in that order (rad or m)."""
        return [self.q_by_joint[name] for name in joints]


# --------------------------------------------------------------------------- internals


def _pin() -> Pinocchio:
    return pin_module("inverse kinematics (motiontool generate)")


class _Chain:
    """The motors the solver moves: their indices in Pinocchio's q and v vectors, and limits."""

    def __init__(self, model: Model, spec: RobotSpec, joints: Sequence[str] | None) -> None:
        import numpy as np

        names = list(spec.joint_names if joints is None else joints)
        if not names:
            raise MotionToolError("inverse kinematics needs at least one joint to move")
        self.names = names
        self.idx_q: list[int] = []
        self.idx_v: list[int] = []
        for name in names:
            if name not in spec:
                raise MotionToolError(unknown_joint_message(name, spec))
            jid = model.getJointId(name)
            if jid >= model.njoints or model.joints[jid].nq != 1 or model.joints[jid].nv != 1:
                raise MotionToolError(
                    f"inverse kinematics moves 1-DoF revolute or prismatic joints only; "
                    f"'{name}' of robot {spec.name} is not one"
                )
            self.idx_q.append(model.joints[jid].idx_q)
            self.idx_v.append(model.joints[jid].idx_v)
        self.lower = np.array([spec.joint(n).lower for n in names], dtype=np.float64)
        self.upper = np.array([spec.joint(n).upper for n in names], dtype=np.float64)


def _frame_id(model: Model, spec: RobotSpec, frame: str) -> int:
    fid = int(model.getFrameId(frame))
    if fid >= model.nframes:
        names = ", ".join(f.name for f in model.frames if f.name != "universe")
        raise MotionToolError(f"robot {spec.name} has no frame '{frame}'; choose one of {names}")
    return fid


def _motor_values(model: Model, spec: RobotSpec, q: npt.NDArray[np.float64]) -> dict[str, float]:
    out = {}
    for name in spec.joint_names:
        joint = model.joints[model.getJointId(name)]
        if joint.nq == 2:
            out[name] = math.atan2(float(q[joint.idx_q + 1]), float(q[joint.idx_q]))
        else:
            out[name] = float(q[joint.idx_q])
    return out


def _residual(
    model: Model,
    data: Data,
    q: npt.NDArray[np.float64],
    fid: int,
    target: SE3,
    chain: _Chain,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """``e = log6(oMf^-1 · oMdes)`` (6,) and ``de/dx`` (6, n) for the chain's motors x."""
    import numpy as np

    pin = _pin()
    pin.forwardKinematics(model, data, q)
    oMf = pin.updateFramePlacement(model, data, fid)
    fMd = oMf.actInv(target)
    error = np.asarray(pin.log6(fMd).vector, dtype=np.float64)
    jac = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL)[:, chain.idx_v]
    return error, -np.asarray(pin.Jlog6(fMd.inverse()) @ jac, dtype=np.float64)


def _pose_of(oMf: SE3) -> Pose:
    import numpy as np

    return Pose(np.array(oMf.translation), np.array(oMf.rotation))


def _descend(
    model: Model,
    data: Data,
    fid: int,
    goal: SE3,
    chain: _Chain,
    q: npt.NDArray[np.float64],
    target: Pose,
    tolerances: tuple[float, float],
    max_iterations: int,
) -> tuple[npt.NDArray[np.float64], float, float, int]:
    """Levenberg–Marquardt from ``q`` (the chain's motors within their limits) until the frame
    is within ``tolerances`` (m, rad) of ``target``, the damping runs away, or
    ``max_iterations``: the last accepted q, its position (m) and orientation (rad) errors and
    the iterations used."""
    import numpy as np

    x = q[chain.idx_q]
    error, jac = _residual(model, data, q, fid, goal, chain)
    cost = float(error @ error)
    lam = _LAMBDA_START
    identity = np.eye(len(chain.names))
    iterations = 0
    position_error, orientation_error = _pose_of(data.oMf[fid]).errors_to(target)
    while position_error > tolerances[0] or orientation_error > tolerances[1]:
        if lam > _LAMBDA_MAX or iterations >= max_iterations:
            break
        iterations += 1
        step = -np.linalg.solve(jac.T @ jac + lam * identity, jac.T @ error)
        largest = float(np.max(np.abs(step)))
        if largest > MAX_STEP:
            step *= MAX_STEP / largest
        x_new = np.clip(x + step, chain.lower, chain.upper)
        q_new = q.copy()
        q_new[chain.idx_q] = x_new
        error_new, jac_new = _residual(model, data, q_new, fid, goal, chain)
        cost_new = float(error_new @ error_new)
        if cost_new < cost:
            x, q, error, jac, cost = x_new, q_new, error_new, jac_new, cost_new
            lam = max(lam / 10.0, _LAMBDA_MIN)
            position_error, orientation_error = _pose_of(data.oMf[fid]).errors_to(target)
        else:
            lam *= 10.0
    return q, position_error, orientation_error, iterations


# --------------------------------------------------------------------------- public functions


def forward_pose(spec: RobotSpec, q_by_joint: Mapping[str, float], frame: str) -> Pose:
    """The pose of ``frame`` in the world frame for motor positions ``q_by_joint`` (rad or m;
    motors left out are at 0)."""
    from motiontool.kinematics._pinocchio import build_model

    pin = _pin()
    model, _geoms = build_model(spec)
    data = model.createData()
    fid = _frame_id(model, spec, frame)
    pin.forwardKinematics(model, data, configuration(model, spec, q_by_joint))
    return _pose_of(pin.updateFramePlacement(model, data, fid))


def frame_jacobian(
    spec: RobotSpec,
    q_by_joint: Mapping[str, float],
    frame: str,
    joints: Sequence[str] | None = None,
) -> npt.NDArray[np.float64]:
    """Jacobian of ``frame``, shape (6, n) float64, one column per joint of ``joints`` (default:
    every motor): rows 0–2 the velocity of the frame's origin (m/s per rad/s or m/s), rows 3–5
    its angular velocity (rad/s per rad/s), both in world axes."""
    import numpy as np

    from motiontool.kinematics._pinocchio import build_model

    pin = _pin()
    model, _geoms = build_model(spec)
    data = model.createData()
    chain = _Chain(model, spec, joints)
    fid = _frame_id(model, spec, frame)
    q = configuration(model, spec, q_by_joint)
    jac = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)
    return np.array(jac[:, chain.idx_v], dtype=np.float64)


def solve_ik(
    spec: RobotSpec,
    target: Pose,
    seed: Mapping[str, float],
    *,
    frame: str,
    joints: Sequence[str] | None = None,
    position_tolerance_m: float = DEFAULT_POSITION_TOLERANCE_M,
    orientation_tolerance_rad: float = DEFAULT_ORIENTATION_TOLERANCE_RAD,
    max_iterations: int = 200,
) -> IKSolution:
    """Motor positions that put ``frame`` at ``target`` (position and orientation).

    Args:
        spec: the robot (its Pinocchio model comes from ``build_model(spec)``).
        target: the wanted pose of ``frame`` in the world (base) frame.
        seed: the start configuration, motor name -> rad (m for slides); motors left out start
            at 0. The solution is the one the solver reaches moving continuously from here,
            so seeding from the previous waypoint keeps a trajectory on one IK branch.
        frame: a frame of the model (body, joint or site name, e.g. ``tool_slot``).
        joints: the motors the solver may move (default: all); the others keep their seed.
        position_tolerance_m: converged when the frame is this close to the target (m) ...
        orientation_tolerance_rad: ... and rotated by at most this angle from it (rad).
        max_iterations: give up after this many iterations.

    Every motor stays within its ``[lower, upper]`` limits; a seed outside them is clamped.

    Raises:
        MotionToolError: unknown frame or joint, or no convergence (the target is out of
            reach, beyond a joint limit, or on another branch than the seed's); the message
            gives the remaining position error in mm and orientation error in degrees.
    """
    import numpy as np

    from motiontool.kinematics._pinocchio import build_model

    pin = _pin()
    model, _geoms = build_model(spec)
    data = model.createData()
    fid = _frame_id(model, spec, frame)
    chain = _Chain(model, spec, joints)
    goal = pin.SE3(np.array(target.rotation), np.array(target.position))
    q = configuration(model, spec, seed)
    q[chain.idx_q] = np.clip(q[chain.idx_q], chain.lower, chain.upper)
    tolerances = (position_tolerance_m, orientation_tolerance_rad)
    search = _descend(model, data, fid, goal, chain, q, target, tolerances, max_iterations)
    q, position_error, orientation_error, iterations = search
    if position_error <= position_tolerance_m and orientation_error <= orientation_tolerance_rad:
        _log.debug(
            "IK %s: converged in %d iterations (%.3g m, %.3g rad)",
            frame,
            iterations,
            position_error,
            orientation_error,
        )
        q_by_joint = _motor_values(model, spec, q)
        return IKSolution(q_by_joint, position_error, orientation_error, iterations)
    raise _no_convergence(spec, frame, target, (position_error, orientation_error), iterations)


def _no_convergence(
    spec: RobotSpec, frame: str, target: Pose, errors: tuple[float, float], iterations: int
) -> MotionToolError:
    """The error of a search that stopped ``errors`` (m, rad) away from ``target``."""
    return MotionToolError(
        f"inverse kinematics for frame '{frame}' of robot {spec.name} did not converge to "
        f"position ({target.position[0]:.4f}, {target.position[1]:.4f}, "
        f"{target.position[2]:.4f}) m: still {errors[0] * MM_PER_M:.1f} mm and "
        f"{math.degrees(errors[1]):.2f} deg away after {iterations} iterations "
        f"(out of reach, beyond a joint limit, or on another branch than the seed)"
    )
