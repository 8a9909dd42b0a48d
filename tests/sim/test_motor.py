"""The Webots motor law, on its own and realised by MuJoCo on a one-joint arm; the command matrix.

The arm: a 1 kg point-like link 0.1 m from a hinge (I = 0.011 kg m^2 about the hinge), on a fixed
base. Its axis is vertical (no gravity torque) for the P-law and velocity-cap tests, horizontal for
the torque tests, where gravity pulls with m g l = 0.981 N m at q = 0.
"""

from __future__ import annotations

import hashlib
import math
from pathlib import Path

import numpy as np
import pytest

from motiontool.kinematics.robots import JointSpec, RobotSpec
from motiontool.motionfmt import read_bytes, sample
from motiontool.sim import MotorLimits, command_matrix, command_stream, velocity_command
from motiontool.sim import _mujoco as mj
from motiontool.sim._mujoco import stepping

ARM = """<mujoco model="arm">
  <compiler angle="radian" autolimits="true"/>
  <worldbody>
    <body name="base">
      <geom type="box" size=".05 .05 .05" pos="0 0 .05"/>
      <body name="link" pos="0 0 0.2">
        <joint name="j" type="hinge" axis="{axis}" range="-3 3"/>
        <inertial pos="0.1 0 0" mass="1" diaginertia="1e-3 1e-3 1e-3"/>
        <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.01"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
GRAVITY_TORQUE = 1.0 * 9.81 * 0.1  # N m, m g l


def arm(tmp_path: Path, *, vertical: bool, max_velocity: float, max_torque: float) -> RobotSpec:
    path = tmp_path / f"arm_{vertical}.xml"
    path.write_text(ARM.format(axis="0 0 1" if vertical else "0 -1 0"))
    joint = JointSpec("j", -3.0, 3.0, max_velocity, max_torque)
    return RobotSpec("arm", path, hashlib.sha256(path.read_bytes()).hexdigest(), (joint,), 20)


def hold(target: float, steps: int) -> tuple[np.ndarray, np.ndarray]:
    return np.full((steps, 1), target), np.ones((steps, 1), dtype=bool)


def test_velocity_command_is_clipped_p_law() -> None:
    limits = MotorLimits(
        lower=np.array([-1.0, -1.0, -1.0]),
        upper=np.array([1.0, 1.0, 1.0]),
        max_velocity=np.array([5.0, 5.0, 5.0]),
        max_torque=np.array([1.0, 1.0, 1.0]),
    )
    target = np.array([0.2, 3.0, -0.9])
    position = np.array([0.1, 0.0, 0.5])
    # 10 * 0.1; target clipped to 1 then 10 * 1 capped at 5; 10 * -1.4 capped at -5.
    assert velocity_command(limits, target, position).tolist() == pytest.approx([1.0, 5.0, -5.0])


@pytest.mark.needs("sim")
def test_p_controller_shrinks_the_error_by_1_minus_pT_every_step(tmp_path: Path) -> None:
    # Webots: the joint moves at Vc = P e for one step T, so e_next = (1 - P T) e = 0.8 e.
    scene = mj.build_scene(arm(tmp_path, vertical=True, max_velocity=5.0, max_torque=10.0), 20)
    trace = mj.run(scene, *hold(0.05, 8))
    error = 0.05 - trace.position[:, 0]
    assert error[1:] / error[:-1] == pytest.approx(np.full(8, 0.8), abs=2e-3)


@pytest.mark.needs("sim")
def test_speed_is_capped_at_max_velocity(tmp_path: Path) -> None:
    scene = mj.build_scene(arm(tmp_path, vertical=True, max_velocity=2.0, max_torque=10.0), 20)
    trace = mj.run(scene, *hold(1.0, 10))
    assert trace.velocity_cmd[:, 0].tolist() == [2.0] * 10
    speed = np.diff(trace.position[:, 0]) / 0.02
    assert speed[1:] == pytest.approx(np.full(9, 2.0), rel=1e-3)
    assert speed[0] == pytest.approx(2.0, rel=0.02)  # the first step accelerates


@pytest.mark.needs("sim")
def test_motor_holds_a_load_below_max_torque(tmp_path: Path) -> None:
    scene = mj.build_scene(arm(tmp_path, vertical=False, max_velocity=5.0, max_torque=2.0), 20)
    trace = mj.run(scene, *hold(0.0, 10))
    assert trace.torque[:, 0] == pytest.approx(np.full(10, GRAVITY_TORQUE), rel=1e-3)
    assert abs(trace.position[-1, 0]) < 1e-3


@pytest.mark.needs("sim")
def test_motor_torque_saturates_at_max_torque(tmp_path: Path) -> None:
    scene = mj.build_scene(arm(tmp_path, vertical=False, max_velocity=5.0, max_torque=0.5), 20)
    trace = mj.run(scene, *hold(0.0, 10))
    assert trace.torque[:, 0] == pytest.approx(np.full(10, 0.5), rel=1e-6)
    assert trace.position[-1, 0] < -0.5  # gravity wins: the arm sags


@pytest.mark.needs("sim")
def test_joint_range_is_not_a_hard_stop(tmp_path: Path) -> None:
    # Webots' PROTOs have no stops: a load pushes a joint past its motor limits.
    robot = arm(tmp_path, vertical=False, max_velocity=5.0, max_torque=0.1)
    narrow = RobotSpec(
        robot.name,
        robot.model_path,
        robot.model_hash,
        (JointSpec("j", -0.1, 0.1, 5.0, 0.1),),
        20,
    )
    trace = mj.run(mj.build_scene(narrow, 20), *hold(0.0, 25))
    assert trace.position[-1, 0] < -0.5


def _motion(text: str):  # type: ignore[no-untyped-def]
    return read_bytes(text.encode()).motion


def test_command_matrix_keeps_targets_without_command_and_chains_motions() -> None:
    a = _motion("#WEBOTS_MOTION,V1.0,A,B\n0,P,1,*\n40,P,2,*\n")
    b = _motion("#WEBOTS_MOTION,V1.0,B\n0,P,5\n20,P,6\n")
    initial = np.array([0.5, -0.5, 9.0])
    targets, commanded, lengths, ignored = command_matrix(
        command_stream([a, b], ["A", "B", "C"], 20, initial, hold_steps=2)
    )
    assert lengths == [3, 2]
    assert ignored == []
    assert targets.tolist() == [
        [1.0, -0.5, 9.0],
        [1.5, -0.5, 9.0],
        [2.0, -0.5, 9.0],
        [2.0, 5.0, 9.0],
        [2.0, 6.0, 9.0],
        [2.0, 6.0, 9.0],
        [2.0, 6.0, 9.0],
    ]
    assert commanded[:, 0].tolist() == [True] * 3 + [False] * 4
    assert commanded[:, 1].tolist() == [False] * 3 + [True] * 2 + [False] * 2


def test_command_matrix_is_the_sample_stream_with_webots_loop_and_reverse() -> None:
    m = _motion("#WEBOTS_MOTION,V1.0,A,X\n0,P,0,1\n100,P,1,1\n150,P,0.5,1\n")
    targets, _c, lengths, ignored = command_matrix(
        command_stream([m], ["A"], 32, np.zeros(1), reverse=True, loops=3)
    )
    stream = sample(m, 32, reverse=True, loops=3)
    assert ignored == ["X"]
    assert lengths == [len(stream.elapsed_ms)]
    assert targets[:, 0].tolist() == stream.targets[:, 0].tolist()  # bit for bit


def test_command_matrix_later_duplicate_column_wins_where_it_has_a_value() -> None:
    m = _motion("#WEBOTS_MOTION,V1.0,A,A\n0,P,1,*\n20,P,2,3\n")
    targets, _c, _l, _i = command_matrix(command_stream([m], ["A"], 20, np.zeros(1)))
    assert targets[:, 0].tolist() == [1.0, 3.0]
    assert not math.isnan(targets[0, 0])


@pytest.mark.needs("sim")
def test_the_control_loop_sends_the_motor_laws_command(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # One law, in sim.motor: the stepping loop calls it instead of a copy of it.
    calls: list[tuple[np.ndarray, np.ndarray]] = []

    def spy(limits: MotorLimits, target: np.ndarray, position: np.ndarray) -> np.ndarray:
        calls.append((target.copy(), position.copy()))
        return velocity_command(limits, target, position)

    monkeypatch.setattr(stepping, "velocity_command", spy)
    scene = mj.build_scene(arm(tmp_path, vertical=True, max_velocity=2.0, max_torque=10.0), 20)
    trace = mj.run(scene, *hold(1.0, 6))
    assert len(calls) == 6
    for k, (target, position) in enumerate(calls):
        assert target.tolist() == [1.0] and position.tolist() == trace.position[k].tolist()
        assert (
            trace.velocity_cmd[k].tolist()
            == velocity_command(scene.limits, target, position).tolist()
        )


def _small_arena_arm(tmp_path: Path) -> RobotSpec:
    """The arm of ARM, its link longer and its base clear of the box it stands on, with a MuJoCo
    arena too small for the contacts of the link falling onto the box: MuJoCo raises
    mujoco.FatalError (out of memory) mid-run."""
    path = tmp_path / "small_arena.xml"
    path.write_text(
        ARM.format(axis="0 -1 0")
        .replace("<worldbody>", '<size memory="4K"/>\n  <worldbody>')
        .replace('pos="0 0 .05"', 'pos="0 0 .1"')
        .replace('fromto="0 0 0 0.2 0 0"', 'fromto="0 0 0 0.3 0 0"')
    )
    joint = JointSpec("j", -3.0, 3.0, 5.0, 0.01)  # too weak to hold the link up
    return RobotSpec("arm", path, hashlib.sha256(path.read_bytes()).hexdigest(), (joint,), 20)


@pytest.mark.needs("sim")
def test_a_mujoco_error_stops_the_run_and_the_trace_says_why(tmp_path: Path) -> None:
    scene = mj.build_scene(_small_arena_arm(tmp_path), 20)
    trace = mj.run(scene, *hold(0.0, 50))
    assert 0 < trace.steps_done < 50
    assert trace.error is not None
    assert trace.error.startswith(f"simulation stopped at step {trace.steps_done}: mj_stackAlloc")
    assert len(trace.position) == trace.steps_done + 1


@pytest.mark.needs("sim")
def test_a_bug_in_our_own_contact_code_is_raised_not_reported_as_a_stopped_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def broken(*args: object) -> None:
        raise IndexError("a bug in motiontool's contact bookkeeping")

    monkeypatch.setattr(stepping, "_contacts", broken)
    scene = mj.build_scene(arm(tmp_path, vertical=False, max_velocity=5.0, max_torque=0.01), 20)
    # Before: trace.error = "simulation stopped at step N: a bug in ...", a clean-looking exit 2.
    with pytest.raises(IndexError, match="contact bookkeeping"):
        mj.run(scene, *hold(0.0, 50))


@pytest.mark.needs("sim")
def test_a_mujoco_error_in_a_later_chunk_stops_the_run_where_one_chunk_does(
    tmp_path: Path,
) -> None:
    """The run stops at the same step, with the same message, whatever the chunks; the chunk it
    stopped in is the last, cut to the steps simulated."""
    from motiontool.sim.trace import concatenate

    whole = mj.run(mj.build_scene(_small_arena_arm(tmp_path), 20), *hold(0.0, 50))
    targets, commanded = hold(0.0, 50)
    pieces = [(targets[k : k + 3], commanded[k : k + 3]) for k in range(0, 50, 3)]
    scene = mj.build_scene(_small_arena_arm(tmp_path), 20)
    chunks = list(mj.run_chunks(scene, pieces))
    assert len(chunks) < len(pieces) and chunks[-1].error == whole.error
    assert all(c.error is None for c in chunks[:-1])
    joined = concatenate(chunks)
    assert joined.steps_done == whole.steps_done
    assert np.array_equal(joined.position, whole.position)
