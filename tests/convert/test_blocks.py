"""The robot exports work a block of control steps at a time, so that what they hold besides
the stream itself does not grow with a motion's duration: the blocks change nothing. Each
test runs an export with blocks of a few steps and with one block, and compares the bytes."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from bags import read_bag
from conftest import ROOT
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import motion_files

from motiontool.errors import MotionToolError
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt import read_bytes, sample
from motiontool.motionfmt.convert import held, naoqi_curve, ros_trajectory, urscript
from motiontool.motionfmt.convert.base import ExportOptions, WorstError
from motiontool.motionfmt.convert.rosbag import write_rosbag
from motiontool.motionfmt.convert.urscript import write_urscript
from motiontool.motionfmt.player import hold_targets

UR = load_robot("ur5e")
ARM = ROOT / "motions" / "ur5e" / "sorting.motion"
NAO = ROOT / "motions" / "nao" / "wave_right.motion"


def _bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a).view(np.int64)


@settings(max_examples=150, deadline=None)
@given(motion_files(), st.integers(1, 7), st.sampled_from([1, 7, 20]))
def test_held_stream_in_chunks_is_the_whole_stream_held(data: bytes, chunk: int, step: int) -> None:
    motion = read_bytes(data, "m.motion").motion
    try:
        whole = sample(motion, step)
    except MotionToolError:
        return  # a stream Webots never ends: refused either way
    names = tuple(dict.fromkeys(motion.joints))
    want = hold_targets(whole.targets, whole.commanded, motion.joints, names).targets
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(held, "_CHUNK_STEPS", chunk)
        try:
            got = held.held_stream(motion, step)
        except MotionToolError:
            assert not np.isfinite(whole.targets[whole.commanded]).all()  # nan/inf refused
            return
    assert got.motors == names
    assert np.array_equal(got.elapsed_ms, whole.elapsed_ms)
    assert np.array_equal(_bits(got.targets), _bits(want))


def test_curve_in_blocks_is_the_curve_in_one() -> None:
    rng = np.random.default_rng(7)
    times = np.cumsum(rng.uniform(0.05, 0.5, 12)).tolist()
    keys = [(float(q), (3, -0.01, 0.02), (3, 0.01, -0.02)) for q in rng.uniform(-1, 1, 12)]
    at = np.linspace(times[0] - 0.3, times[-1] + 0.3, 501)
    one = naoqi_curve.curve_at(times, keys, at)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(naoqi_curve, "_TIMES", 7)
        blocks = naoqi_curve.curve_at(times, keys, at)
    assert np.isnan(one[at < times[0]]).all() and not np.isnan(one[at >= times[0]]).any()
    assert np.array_equal(_bits(blocks), _bits(one), equal_nan=False)


@pytest.mark.parametrize(
    "err",
    [
        np.array([[0.0, 0.0], [0.0, 0.0]]),  # nothing: the first entry
        np.array([[0.1, 0.3], [0.3, 0.2], [0.1, 0.3]]),  # ties: the first in row order
        np.random.default_rng(3).uniform(0, 1, (50, 4)),
        np.zeros((0, 3)),
    ],
)
@pytest.mark.parametrize("rows", [1, 2, 5, 100])
def test_worst_error_in_blocks_is_argmax_of_the_whole(err: np.ndarray, rows: int) -> None:
    worst = WorstError()
    times = np.arange(err.shape[0], dtype=np.int64) * 20 + 5
    for lo in range(0, err.shape[0], rows):
        worst.update(err[lo : lo + rows], lo, times[lo : lo + rows])
    if err.size == 0:
        assert (worst.rad, worst.row, worst.column, worst.at_ms) == (0.0, 0, 0, None)
        return
    row, column = np.unravel_index(int(np.argmax(err)), err.shape)
    assert (worst.rad, worst.row, worst.column) == (err[row, column], row, column)
    assert worst.at_ms == times[row]


def _export(module: object, name: str, rows: int, run: object) -> object:
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(module, name, rows)
        return run()  # type: ignore[operator]


def test_urscript_in_blocks_is_the_program_in_one() -> None:
    motion = read_bytes(ARM.read_bytes(), str(ARM)).motion
    options = ExportOptions(timestep_ms=8, joint_order=UR.joint_names, robot="ur5e")
    big = _export(urscript, "_ROWS", 1 << 30, lambda: write_urscript(motion, options))
    small = _export(urscript, "_ROWS", 5, lambda: write_urscript(motion, options))
    assert small.data == big.data and small.poses == big.poses  # type: ignore[attr-defined]
    assert small.deviation == big.deviation  # type: ignore[attr-defined]
    assert big.poses > 5  # type: ignore[attr-defined]


def test_trajectory_deviation_in_blocks_is_the_deviation_in_one() -> None:
    motion = read_bytes(NAO.read_bytes(), str(NAO)).motion
    traj = ros_trajectory.trajectory(motion, ExportOptions(timestep_ms=20))
    assert traj.steps > 10
    # Points made sparser by hand: a deviation that is not 0, wherever the worst step is.
    sparse = dataclasses.replace(
        traj, elapsed_ms=traj.elapsed_ms[::3], positions=traj.positions[::3], lead_in_ms=0
    )
    for t in (traj, sparse):
        one = _export(ros_trajectory, "_ROWS", 1 << 30, lambda t=t: ros_trajectory.deviation(t))
        few = _export(ros_trajectory, "_ROWS", 3, lambda t=t: ros_trajectory.deviation(t))
        assert few == one
    assert one.max_rad > 0.0  # type: ignore[attr-defined]


@pytest.mark.needs("ros", "sim")
def test_a_bag_is_written_from_messages_made_as_it_goes(tmp_path: Path) -> None:
    """The JointState messages are made while the bag is written (a generator): the bag
    holds one per step, in order (its bytes are checked by tests/convert/test_ros.py)."""
    motion = read_bytes(NAO.read_bytes(), str(NAO)).motion
    exported = write_rosbag(motion, ExportOptions(timestep_ms=20))
    path = tmp_path / "b.mcap"
    path.write_bytes(exported.data)
    steps = held.held_stream(motion, 20).elapsed_ms
    messages = read_bag(path)["/joint_states sensor_msgs/msg/JointState"]
    assert exported.poses == len(messages) == steps.shape[0]
    assert [ns for ns, _ in messages] == (steps * 1_000_000).tolist()
