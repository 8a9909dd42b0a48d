"""The Ray executor against a real Ray head started on loopback by this test."""

from __future__ import annotations

import json
import shutil
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import ROOT
from raycluster import free_port, ray_cluster
from rrds import rrd_rows

from motiontool.cli.batch_progress import in_flight
from motiontool.kinematics.robots import load_robot
from motiontool.sim.batch import parse_perturbation, plan, run_batch
from motiontool.sim.executor import DEFAULT_JOBS, Parallelism, session
from motiontool.sim.runs import run_spec

pytestmark = pytest.mark.needs("sim", "ray")


@pytest.fixture(scope="module")
def ray_head(one_ray: None) -> Iterator[str]:
    """A two-node cluster on loopback, as ``ray start`` makes one: a head and a worker node,
    each started from a folder of its own (their workers' working folders), one CPU each."""
    with ray_cluster(nodes=2) as address:
        yield address


@pytest.mark.slow
def test_ray_gives_the_local_results(ray_head: str) -> None:
    motion = ROOT / "motions" / "nao" / "head_no.motion"
    specs = plan(
        [motion], ["nao"], perturbations=[parse_perturbation("friction=0.8:1.2")], samples=2, seed=7
    )

    def model_hash(robot: str) -> str:
        return load_robot(robot).model_hash

    local = run_batch(
        specs, run_spec, model_hash=model_hash, executor="local", jobs=2, cache_dir=None
    )
    remote = run_batch(
        specs,
        run_spec,
        model_hash=model_hash,
        executor="ray",
        jobs=2,
        cache_dir=None,
        ray_address=ray_head,
    )
    assert [r.status for r in remote.runs] == [r.status for r in local.runs] == ["clean", "clean"]
    for run in remote.runs:  # the worker's host stamped: the only difference
        assert run.report is not None and run.report["stamps"].pop("host")
    assert [r.report for r in remote.runs] == [r.report for r in local.runs]  # bit for bit
    assert remote.executor == "ray"


def _batch(cwd: Path, *args: str) -> subprocess.CompletedProcess[str]:
    script = Path(sys.executable).parent / "motiontool"
    return subprocess.run(
        [str(script), "batch", "motions/head_no.motion", "motions/bow.motion", "--isolated",
         "--no-cache", "--rrd-dir", "rrd", "--json", "report.json", *args],
        cwd=cwd, capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip


def _runs(report: Path) -> list[dict[str, Any]]:
    """The runs of a batch report, without what differs between executors: timings, the
    worker's host."""
    runs = json.loads(report.read_text())["runs"]
    for run in runs:
        run.pop("wall_s")
        run["report"]["stamps"].pop("host", None)
    return list(runs)


@pytest.mark.slow
def test_a_cluster_plays_relative_paths_and_returns_the_recordings(
    ray_head: str, tmp_path: Path
) -> None:
    """Run from a third folder with relative paths, that neither node's workers can resolve:
    every motion travels as bytes, and every recording comes back to the driver."""
    drivers = {"local": tmp_path / "local", "ray": tmp_path / "ray"}
    for folder in drivers.values():
        (folder / "motions").mkdir(parents=True)
        for name in ("head_no", "bow"):
            shutil.copy(ROOT / "motions" / "nao" / f"{name}.motion", folder / "motions")
    local = _batch(drivers["local"])
    remote = _batch(drivers["ray"], "--executor", "ray", "--ray-address", ray_head, "-j", "2")
    assert local.returncode == 0, local.stderr
    assert remote.returncode == 0, remote.stdout + remote.stderr
    for name in ("head_no.nao.0.rrd", "bow.nao.0.rrd"):
        want = rrd_rows(drivers["local"] / "rrd" / name, skip=("/__properties",))
        got = rrd_rows(drivers["ray"] / "rrd" / name, skip=("/__properties",))
        assert got == want, name
    runs = _runs(drivers["ray"] / "report.json")
    assert [r["status"] for r in runs] == ["clean", "clean"]
    assert runs == _runs(drivers["local"] / "report.json")
    hosts = {json.loads((drivers["ray"] / "report.json").read_text())["runs"][0]["report"][
        "stamps"]["host"]}  # fmt: skip
    assert hosts == {socket.gethostname()}


def test_an_unreachable_cluster_is_one_line(tmp_path: Path) -> None:
    (tmp_path / "motions").mkdir()
    shutil.copy(ROOT / "motions" / "nao" / "bow.motion", tmp_path / "motions")
    shutil.copy(ROOT / "motions" / "nao" / "head_no.motion", tmp_path / "motions")
    done = _batch(tmp_path, "--executor", "ray", "--ray-address", f"127.0.0.1:{free_port()}")
    assert done.returncode == 2
    assert done.stderr.startswith("motiontool: error: cannot reach the Ray cluster at")
    assert len(done.stderr.splitlines()) == 1, done.stderr


@pytest.mark.slow
def test_runs_in_flight_are_the_cluster_cpus_at_most_jobs(ray_head: str, tmp_path: Path) -> None:
    """Without --jobs, a batch keeps as many runs in flight as the cluster has CPUs (two nodes
    of one CPU); --jobs caps them; stderr and the report say how many."""
    (tmp_path / "motions").mkdir()
    for name in ("head_no", "bow"):
        shutil.copy(ROOT / "motions" / "nao" / f"{name}.motion", tmp_path / "motions")
    for jobs, said in [
        ((), "2 runs in flight (the cluster's 2 CPUs)"),
        (("-j", "1"), "1 run in flight (--jobs 1; the cluster has 2 CPUs)"),
    ]:
        done = _batch(tmp_path, "--executor", "ray", "--ray-address", ray_head, *jobs)
        assert done.returncode == 0, done.stdout + done.stderr
        assert f"motiontool: ray: {said}" in done.stderr.splitlines()
        report = json.loads((tmp_path / "report.json").read_text())
        assert report["jobs"] == int(said.split()[0])
        assert f"(ray, {said.split()[0]} jobs)" in done.stdout
    with session("ray", 8, address=ray_head) as parallel:
        assert parallel == Parallelism(in_flight=2, cpus=2, asked=8)
    assert in_flight(parallel) == "2 runs in flight (the cluster's 2 CPUs; --jobs 8 is more)"


def test_the_local_pool_keeps_its_default() -> None:
    with session("local", None) as parallel:
        assert parallel == Parallelism(in_flight=DEFAULT_JOBS, cpus=None, asked=None)
    with session("local", 5) as parallel:
        assert parallel.in_flight == 5
