"""Batch runs shipped as bytes (sim/shipped.py): a worker that cannot see the driver's files
still plays the run and hands back its recording (the Ray executor's tasks)."""

from __future__ import annotations

import pickle
import shutil
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest
from conftest import ROOT
from rrds import rrd_rows

from motiontool.errors import MotionToolError
from motiontool.sim.batch import plan
from motiontool.sim.runs import run_spec
from motiontool.sim.shipped import Parcel, Shipped, land, open_parcel, pack

_WORKER = """
import pickle, sys
from motiontool.sim.runs import run_spec
from motiontool.sim.shipped import open_parcel
parcel = pickle.loads(sys.stdin.buffer.read())
sys.stdout.buffer.write(pickle.dumps(open_parcel(run_spec, parcel, store=bytes)))
"""


def _spec(tmp_path: Path, rrd: Path) -> object:
    tree = tmp_path / "tree"
    tree.mkdir()
    motion = tree / "head_no.motion"
    shutil.copy(ROOT / "motions" / "nao" / "head_no.motion", motion)
    (spec,) = plan([motion], ["nao"], options={"rrd_dir": str(rrd), "rrd_name": "head_no"})
    parcel = pack(spec)
    shutil.rmtree(tree)  # what the worker cannot see: the driver's tree is gone
    return parcel


@pytest.mark.needs("sim")
def test_a_worker_that_cannot_see_the_motion_plays_it_from_shipped_bytes(tmp_path: Path) -> None:
    rrd = tmp_path / "rrd"
    rrd.mkdir()
    parcel = _spec(tmp_path, rrd)
    worker = tmp_path / "worker"
    worker.mkdir()
    done = subprocess.run(
        [sys.executable, "-c", _WORKER],
        input=pickle.dumps(parcel),
        capture_output=True,
        cwd=worker,
        check=True,
        timeout=300,
    )
    shipped = pickle.loads(done.stdout)
    assert isinstance(shipped, Shipped)
    assert not list(rrd.iterdir()), "the worker wrote nothing on the driver's side"
    report = land(shipped, fetch=bytes)
    assert report["clean"], report["reason"]
    assert report["files"][0]["path"] == str(tmp_path / "tree" / "head_no.motion")  # driver's
    assert report["stamps"]["host"]
    recording = rrd / "head_no.nao.0.rrd"
    assert rrd_rows(recording), "the recording came back and reads"


def test_a_worker_of_another_version_refuses_the_run(tmp_path: Path) -> None:
    rrd = tmp_path / "rrd"
    rrd.mkdir()
    parcel = _spec(tmp_path, rrd)
    assert isinstance(parcel, Parcel)
    older = replace(parcel, versions=(("motiontool", "0.0.1"), *parcel.versions[1:]))
    with pytest.raises(MotionToolError, match=r"has motiontool \S+, the driver 0\.0\.1"):
        open_parcel(run_spec, older, store=bytes)


@pytest.mark.needs("sim")
def test_a_world_and_its_local_protos_travel_with_the_run(tmp_path: Path) -> None:
    from motiontool.sim.world_run import world_run_options

    tree = tmp_path / "tree"
    shutil.copytree(ROOT / "tests" / "data" / "worlds" / "wrestling", tree / "wrestling")
    shutil.copy(ROOT / "motions" / "nao" / "head_no.motion", tree)
    world = tree / "wrestling" / "worlds" / "wrestling.wbt"
    options = world_run_options(world, "participant", ["nao"])
    (spec,) = plan([tree / "head_no.motion"], ["nao"], options=options)
    parcel = pack(spec)
    assert isinstance(parcel, Parcel)
    shipped = {Path(at).name for _, at, _ in parcel.files}
    assert {"wrestling.wbt", "WrestlingRing.proto"} <= shipped
    want = run_spec(spec)
    shutil.rmtree(tree)  # the worker sees only the parcel
    got = land(open_parcel(run_spec, parcel, store=bytes), fetch=bytes)
    got["stamps"].pop("host")
    assert got == want
    assert str(world) in str(got["world"])  # the driver's world, as the user named it
