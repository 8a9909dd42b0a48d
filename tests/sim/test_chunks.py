"""A run is simulated and measured a chunk of control steps at a time (sim/commands.py
CHUNK_STEPS): the physics is the same whatever the chunks, the report the same (sums of many
terms to rounding), and memory does not grow with the run's duration."""

from __future__ import annotations

import itertools
import math
import tracemalloc
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from motiontool.sim import PlayOptions, _mujoco, commands, play
from motiontool.sim.start import StartState
from motiontool.sim.trace import Trace, concatenate

pytestmark = pytest.mark.needs("sim")

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data" / "corpus" / "webots"
SUMS = {"rms_error", "yaw_change_deg", "slip_m"}
"""Report numbers that sum many terms: chunks add them in another order."""


def same_report(a: Any, b: Any, key: str = "") -> None:
    """The two JSON reports are equal; ``SUMS`` to rounding."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b), key
        for k in a:
            same_report(a[k], b[k], k)
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), key
        for x, y in zip(a, b, strict=True):
            same_report(x, y, key)
    elif key in SUMS and isinstance(a, float):
        assert math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15), (key, a, b)
    else:
        assert a == b, (key, a, b)


def chunked_play(monkeypatch: pytest.MonkeyPatch, steps: int, *args: Any, **kw: Any) -> Any:
    with monkeypatch.context() as m:
        m.setattr(commands, "CHUNK_STEPS", steps)
        return play(*args, **kw).to_json()


def corpus(name: str) -> Path:
    path = next(DATA.rglob(name), None)
    if path is None:
        pytest.skip(f"{name} is not vendored")
    return path


@pytest.mark.parametrize(
    ("motion", "robot", "options"),
    [
        (ROOT / "motions" / "nao" / "bow.motion", "nao", PlayOptions()),
        (ROOT / "motions" / "ur5e" / "sorting.motion", "ur5e", PlayOptions(loops=2, reverse=True)),
        (ROOT / "motions" / "ur5e" / "jog.motion", "ur5e", PlayOptions(hold_s=0.3)),
    ],
    ids=["nao-bow", "ur5e-sorting-reverse-loops", "ur5e-jog"],
)
def test_a_run_in_small_chunks_reports_what_one_chunk_does(
    monkeypatch: pytest.MonkeyPatch, motion: Path, robot: str, options: PlayOptions
) -> None:
    whole = chunked_play(monkeypatch, 1 << 30, [motion], robot=robot, options=options)
    for steps in (1, 7, 64):
        same_report(whole, chunked_play(monkeypatch, steps, [motion], robot=robot, options=options))


def test_a_fall_and_its_contacts_are_measured_across_chunks(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    fall = corpus("Fall.motion")
    whole = chunked_play(monkeypatch, 1 << 30, [fall], robot="nao")
    assert whole["base"]["fell"] and whole["ground_contacts"], "the motion no longer falls"
    for steps in (1, 9):
        same_report(whole, chunked_play(monkeypatch, steps, [fall], robot="nao"))


def test_chunks_join_into_the_trace_of_one_run() -> None:
    """The physics does not see the chunks: the same arrays, bit for bit, and each chunk's
    frame 0 is the last frame of the one before."""
    from motiontool.kinematics import resolve_robot

    spec = resolve_robot("nao")
    rng = np.random.default_rng(3)
    targets = np.clip(rng.normal(0.0, 0.2, (40, len(spec.joint_names))), -0.3, 0.3)
    commanded = np.ones(targets.shape, dtype=bool)

    def scene() -> Any:
        return _mujoco.build_scene(spec, 20, physics_step_ms=2.0, start=StartState.STANDING)

    whole = _mujoco.run(scene(), targets, commanded, record_bodies=True)
    pieces = [(targets[k : k + 13], commanded[k : k + 13]) for k in range(0, 40, 13)]
    chunks = list(_mujoco.run_chunks(scene(), pieces, record_bodies=True))
    assert [c.first_frame for c in chunks] == [0, 13, 26, 39]
    for before, after in itertools.pairwise(chunks):
        assert np.array_equal(before.position[-1], after.position[0])
        assert before.last_frame == after.first_frame
    joined: Trace = concatenate(chunks)
    for name in ("time_s", "targets", "velocity_cmd", "torque", "position", "base_pos"):
        assert np.array_equal(getattr(joined, name), getattr(whole, name)), name
    assert np.array_equal(joined.body_quat, whole.body_quat)
    assert joined.events == whole.events and joined.steps_done == whole.steps_done == 40


def peak_kib(fn: Any) -> float:
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1] / 1024
    finally:
        tracemalloc.stop()


def test_memory_of_a_run_does_not_grow_with_its_duration(monkeypatch: pytest.MonkeyPatch) -> None:
    """Four times the loops, the same peak: nothing of a chunk is kept (here 50 steps a chunk;
    before, a run held every step's arrays, about 1 kB a step on the Nao)."""
    motion = ROOT / "motions" / "nao" / "head_no.motion"
    monkeypatch.setattr(commands, "CHUNK_STEPS", 50)

    def run(loops: int) -> None:
        play([motion], robot="nao", options=PlayOptions(loops=loops, hold_s=0.0))

    run(1)  # imports and caches
    short, long = peak_kib(lambda: run(2)), peak_kib(lambda: run(8))
    assert long < 1.15 * short, (short, long)


@pytest.mark.parametrize(
    ("motion", "robot", "steps"),
    [
        (ROOT / "motions" / "nao" / "bow.motion", "nao", 7),
        (ROOT / "motions" / "ur5e" / "jog.motion", "ur5e", 13),
        ("Fall.motion", "nao", 9),
    ],
    ids=["nao", "ur5e", "nao-fall"],
)
@pytest.mark.needs("rerun", "ros")
def test_recording_and_bag_logged_a_chunk_at_a_time_hold_what_one_chunk_does(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, motion: Path | str, robot: str, steps: int
) -> None:
    """Every entity and column of the recording holds the same rows (events, limits and the
    base's whole path included: a fall and the contacts with the floor too), and the bag the
    same messages, whatever the chunks."""
    from bags import read_bag
    from rrds import rrd_rows

    motion = corpus(motion) if isinstance(motion, str) else motion

    def outputs(chunk_steps: int, name: str) -> tuple[Any, Any]:
        rrd, bag = tmp_path / f"{name}.rrd", tmp_path / f"{name}.mcap"
        with monkeypatch.context() as m:
            m.setattr(commands, "CHUNK_STEPS", chunk_steps)
            play([motion], robot=robot, rrd=rrd, bag=bag, stamps={"motiontool": "x"})
        messages = {
            topic: [(ns, repr(msg)) for ns, msg in rows] for topic, rows in read_bag(bag).items()
        }
        return rrd_rows(rrd), messages

    whole_rrd, whole_bag = outputs(1 << 30, "whole")
    cut_rrd, cut_bag = outputs(steps, "cut")
    assert any(entity == "/events" for entity, _ in whole_rrd)  # the motion's start at least
    if "Fall" in motion.name:
        events = " ".join(whole_rrd[("/events", "TextLog:text")])
        assert "fell" in events and "on the floor" in events, events[:300]
    assert set(cut_rrd) == set(whole_rrd)
    for key, rows in whole_rrd.items():
        assert cut_rrd[key] == rows, key
    assert cut_bag == whole_bag and whole_bag


def test_a_run_of_more_steps_than_a_run_simulates_is_refused_before_it_starts(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from motiontool.errors import MotionToolError

    motion = ROOT / "motions" / "nao" / "head_no.motion"
    monkeypatch.setattr(commands, "MAX_RUN_STEPS", 100)
    with pytest.raises(MotionToolError, match=r"the run: [\d,]+ control steps of 20 ms .* 100 a"):
        play([motion], robot="nao", options=PlayOptions(loops=3))


@pytest.mark.needs("rerun")
def test_a_recording_whose_temporary_file_fails_is_one_error_and_no_file(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """Rerun's file sink stops on a full disk (its flush raises): one MotionToolError naming
    the recording, nothing at the destination, no temporary file left."""
    import rerun as rr

    from motiontool.errors import MotionToolError

    def full(self: Any, *args: Any, **kwargs: Any) -> None:
        raise RuntimeError("File-writer thread shut down prematurely")

    monkeypatch.setenv("TMPDIR", str(tmp_path / "tmp"))
    (tmp_path / "tmp").mkdir()
    monkeypatch.setattr("tempfile.tempdir", None)  # TMPDIR read again
    monkeypatch.setattr(rr.RecordingStream, "flush", full)
    rrd = tmp_path / "run.rrd"
    with pytest.raises(
        MotionToolError, match=r"cannot write the recording '.*run\.rrd'.*disk full"
    ):
        play([ROOT / "motions" / "nao" / "head_no.motion"], robot="nao", rrd=rrd)
    assert not rrd.exists() and not any((tmp_path / "tmp").iterdir())


def test_a_run_tells_how_far_it_is_after_each_chunk(monkeypatch: pytest.MonkeyPatch) -> None:
    """play's progress: the simulated seconds done after each chunk, up to the whole run."""
    monkeypatch.setattr(commands, "CHUNK_STEPS", 20)
    told: list[tuple[float, float]] = []
    report = play(
        [ROOT / "motions" / "nao" / "head_no.motion"],
        robot="nao",
        progress=lambda done, total: told.append((done, total)),
    )
    assert len(told) == -(-report.control_steps // 20)
    assert [t for _, t in told] == [report.simulated_s] * len(told)
    done = [d for d, _ in told]
    assert done == sorted(done) and done[0] == pytest.approx(0.4) and done[-1] == report.simulated_s
