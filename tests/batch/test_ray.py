"""The Ray executor against a real Ray head started on loopback by this test."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from conftest import ROOT

from motiontool.kinematics.robots import load_robot
from motiontool.sim.batch import parse_perturbation, plan, run_batch
from motiontool.sim.runs import run_spec

pytest.importorskip(
    "ray", reason="the Ray executor is an optional extra: pip install 'motiontool[ray]'"
)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="module")
def ray_head(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    ray_bin = shutil.which("ray", path=str(Path(sys.executable).parent))
    assert ray_bin, "the 'ray' command is not installed next to this Python"
    port = _free_port()
    temp = tmp_path_factory.mktemp("ray")
    # Hermetic: `ray start` turns token auth on when it finds ~/.ray/auth_token (left by an earlier
    # local Ray); this head gets a home of its own, so it runs without auth like the driver.
    env = {**os.environ, "HOME": str(temp)}
    subprocess.run(
        [ray_bin, "start", "--head", "--node-ip-address=127.0.0.1", f"--port={port}", "--num-cpus=2",
         "--include-dashboard=false", "--disable-usage-stats", f"--temp-dir={temp}"],
        check=True, capture_output=True, timeout=120, env=env,
    )  # fmt: skip
    try:
        yield f"127.0.0.1:{port}"
    finally:
        subprocess.run(
            [ray_bin, "stop", "--force"], capture_output=True, timeout=120, check=False, env=env
        )


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
    assert [r.report for r in remote.runs] == [r.report for r in local.runs]  # bit for bit
    assert remote.executor == "ray"
