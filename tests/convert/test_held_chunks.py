"""Webots' held stream made a chunk of steps at a time: corner keys found across chunks are
those of the whole stream, and the exports that never hold the stream (NAOqi, the ROS
trajectory, the bag's messages, URScript's servoj lines) write the same bytes, deviation and stream whatever the chunk
size, past the steps a held stream may have."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from hypothesis import given, settings
from hypothesis import strategies as st

from motiontool.cli.convert_checks import stream_findings
from motiontool.errors import MotionToolError
from motiontool.kinematics.robots import load_robot
from motiontool.motionfmt import player, read_bytes
from motiontool.motionfmt.convert import held, urscript
from motiontool.motionfmt.convert.base import ExportOptions, RobotStream
from motiontool.motionfmt.convert.held import Corners, corner_keys, held_stream
from motiontool.motionfmt.convert.naoqi import write_naoqi
from motiontool.motionfmt.convert.ros_trajectory import trajectory, write_ros_trajectory
from motiontool.motionfmt.convert.rosbag import write_rosbag
from motiontool.motionfmt.convert.urscript import write_urscript

NAO_FILES = sorted((ROOT / "motions" / "nao").glob("*.motion"))


@settings(max_examples=200, deadline=None)
@given(
    steps=st.lists(st.sampled_from([0.0, 0.0, 0.5, -0.25, 1e-13, 0.3]), max_size=40),
    cuts=st.lists(st.integers(0, 40), max_size=6),
)
def test_corners_across_chunks_are_the_corners_of_the_whole(
    steps: list[float], cuts: list[int]
) -> None:
    # Straight runs (equal steps), corners, steps under COLLINEAR_RAD; any cuts.
    values = np.cumsum(np.asarray(steps, dtype=np.float64))
    at = np.arange(values.shape[0], dtype=np.int64) * 20 + 7
    corners = Corners()
    bounds = sorted({0, values.shape[0], *(c % (values.shape[0] + 1) for c in cuts)})
    for a, b in itertools.pairwise(bounds):
        corners.add(at[a:b], values[a:b])
    got_at, got_values = corners.keys()
    want = corner_keys(values)
    assert corners.count == values.shape[0]
    assert got_at.tolist() == at[want].tolist()
    assert got_values.tobytes() == values[want].tobytes()


def _export(path: Path, chunk_steps: int, monkeypatch: pytest.MonkeyPatch) -> tuple[object, ...]:
    monkeypatch.setattr(held, "_CHUNK_STEPS", chunk_steps)
    motion = read_bytes(path.read_bytes()).motion
    out = write_naoqi(motion, ExportOptions(timestep_ms=20, robot="nao"))
    spec = load_robot("nao")
    assert out.stream is not None
    found = stream_findings(out.stream, spec, "naoqi")
    rows = list(out.stream.chunks())
    times = np.concatenate([t for t, _ in rows])
    targets = np.concatenate([q for _, q in rows])
    return out.data, out.deviation, found, times.tobytes(), targets.tobytes()


@pytest.mark.parametrize("path", [*NAO_FILES[:3], None], ids=lambda p: p.stem if p else "held")
def test_naoqi_is_the_same_whatever_the_chunk_size(
    path: Path | None, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    if path is None:  # no deviation at all: the first step of the first motor is named
        path = tmp_path / "held.motion"
        path.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,A,0,0\n400,B,0,0\n")
    whole = _export(path, 1 << 20, monkeypatch)  # one chunk
    assert _export(path, 7, monkeypatch) == whole


def test_naoqi_exports_a_stream_longer_than_one_may_hold(monkeypatch: pytest.MonkeyPatch) -> None:
    motion = read_bytes(NAO_FILES[0].read_bytes()).motion
    monkeypatch.setattr(player, "MAX_HELD_STEPS", 50)
    with pytest.raises(MotionToolError, match="more than the 50"):
        held_stream(motion, 20)
    out = write_naoqi(motion, ExportOptions(timestep_ms=20, robot="nao"))
    assert out.poses > 0 and out.deviation is not None and out.deviation.max_rad < 1e-9
    assert isinstance(out.stream, RobotStream) and out.stream.made is not None


@pytest.mark.needs("ros", "sim")
@pytest.mark.parametrize("path", NAO_FILES[:2], ids=lambda p: p.stem)
def test_ros_formats_are_the_same_whatever_the_chunk_size(
    path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    motion = read_bytes(path.read_bytes()).motion
    options = ExportOptions(timestep_ms=20, robot="nao")

    def export(chunk_steps: int) -> tuple[object, ...]:
        monkeypatch.setattr(held, "_CHUNK_STEPS", chunk_steps)
        traj, bag = write_ros_trajectory(motion, options), write_rosbag(motion, options)
        assert bag.stream is not None
        found = stream_findings(bag.stream, load_robot("nao"), "rosbag")
        return traj.data, traj.deviation, bag.data, bag.deviation, bag.poses, found

    assert export(7) == export(1 << 20)


def test_a_trajectory_is_found_in_a_stream_longer_than_one_may_hold(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    motion = read_bytes(NAO_FILES[0].read_bytes()).motion
    whole = trajectory(motion, ExportOptions(timestep_ms=20))
    monkeypatch.setattr(player, "MAX_HELD_STEPS", 50)
    monkeypatch.setattr(held, "_CHUNK_STEPS", 16)
    chunked = trajectory(motion, ExportOptions(timestep_ms=20))
    assert chunked.steps == whole.steps > 50
    assert chunked.elapsed_ms.tolist() == whole.elapsed_ms.tolist()
    assert chunked.positions.tobytes() == whole.positions.tobytes()


@pytest.mark.parametrize("blend", [None, 40.0], ids=["corners", "blended"])
@pytest.mark.parametrize("lossy", [False, True], ids=["exact", "lossy"])
@pytest.mark.parametrize("name", ["jog", "sorting"])
def test_urscript_is_the_same_whatever_the_chunk_size(
    name: str, lossy: bool, blend: float | None, monkeypatch: pytest.MonkeyPatch
) -> None:
    if lossy:  # numbers written to 4 decimals: a deviation, at a step the report must name
        monkeypatch.setattr(urscript, "number", lambda v: f"{v:.4f}")
    motion = read_bytes((ROOT / "motions" / "ur5e" / f"{name}.motion").read_bytes()).motion
    ur = load_robot("ur5e")
    options = ExportOptions(
        timestep_ms=8, robot="ur5e", joint_order=ur.joint_names, blend_rad_s2=blend
    )

    def export(chunk_steps: int) -> tuple[object, ...]:
        monkeypatch.setattr(held, "_CHUNK_STEPS", chunk_steps)
        out = write_urscript(motion, options)
        assert out.stream is not None
        found = stream_findings(out.stream, ur, "urscript")
        return out.data, out.deviation, out.poses, found

    whole = export(1 << 20)
    exact = not lossy and blend is None
    assert whole[1].max_rad == 0 if exact else whole[1].max_rad > 0  # type: ignore[attr-defined]
    monkeypatch.setattr(player, "MAX_HELD_STEPS", 50)  # never held: not refused
    assert export(7) == whole


def test_an_export_past_its_steps_is_refused_in_one_line(monkeypatch: pytest.MonkeyPatch) -> None:
    motion = read_bytes(NAO_FILES[0].read_bytes()).motion
    monkeypatch.setattr(held, "MAX_EXPORT_STEPS", 50)
    for write in (write_naoqi, write_ros_trajectory, write_rosbag):
        with pytest.raises(MotionToolError, match=r"more than the 50 an export makes"):
            write(motion, ExportOptions(timestep_ms=20, robot="nao"))
