"""Ray clusters that cannot play a batch as they are: one whose Python lacks motiontool (one
line, exit 2), and the same cluster given motiontool through ``--ray-runtime-env``."""

from __future__ import annotations

import json
import re
import shutil
import socket
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest
from conftest import ROOT
from raycluster import python_without_motiontool, ray_cluster

pytestmark = pytest.mark.needs("sim", "ray")

_MOTIONS = ("head_no", "bow")


@pytest.fixture(scope="module")
def bare_head(one_ray: None) -> Iterator[str]:
    """A one-node cluster whose Python has Ray and MuJoCo but not motiontool."""
    folder = Path(tempfile.mkdtemp(prefix="mtenv"))
    try:
        with ray_cluster(nodes=1, python=python_without_motiontool(folder)) as address:
            yield address
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _batch(cwd: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """``motiontool batch`` of two motions, from ``cwd`` with relative paths, on Ray."""
    (cwd / "motions").mkdir(exist_ok=True)
    for name in _MOTIONS:
        shutil.copy(ROOT / "motions" / "nao" / f"{name}.motion", cwd / "motions")
    script = Path(sys.executable).parent / "motiontool"
    files = [f"motions/{name}.motion" for name in _MOTIONS]
    return subprocess.run(
        [str(script), "batch", *files, "--isolated", "--no-cache", "--json", "report.json",
         "--executor", "ray", *args],
        cwd=cwd, capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip


def _shipped(tmp_path: Path) -> str:
    """A JSON file of a runtime environment that ships this checkout's package folder as
    ``py_modules`` (a copy named ``motiontool``, as an installed package's folder is)."""
    package = tmp_path / "ship" / "motiontool"
    skip = shutil.ignore_patterns(".*", "build", "tests", "dev", "docs", "benchmarks", "*.egg-info")
    shutil.copytree(ROOT, package, ignore=skip)
    env = tmp_path / "env.json"
    env.write_text(json.dumps({"py_modules": [str(package)]}))
    return str(env)


@pytest.mark.slow
def test_a_cluster_without_motiontool_is_one_line(bare_head: str, tmp_path: Path) -> None:
    done = _batch(tmp_path, "--ray-address", bare_head)
    assert done.returncode == 2, done.stdout + done.stderr
    said, error = done.stderr.splitlines()
    assert said == "motiontool: ray: 1 run in flight (the cluster's 1 CPU)"
    assert re.fullmatch(
        r"motiontool: error: the Ray workers cannot import motiontool or its simulation"
        r" libraries \(No module named 'motiontool', on [0-9.]+\): install motiontool\[sim\] in"
        r" the cluster's image or pass --ray-runtime-env \(docs/ray.md\)",
        error,
    ), error
    assert not (tmp_path / "report.json").exists()


@pytest.mark.slow
def test_a_runtime_env_ships_motiontool_to_it(bare_head: str, tmp_path: Path) -> None:
    """The package folder as ``py_modules`` (a copy named ``motiontool``, as an installed
    package's folder is), from a JSON file: every run plays on the cluster."""
    done = _batch(tmp_path, "--ray-address", bare_head, "--ray-runtime-env", _shipped(tmp_path))
    assert done.returncode == 0, done.stdout + done.stderr
    runs = json.loads((tmp_path / "report.json").read_text())["runs"]
    assert [r["status"] for r in runs] == ["clean", "clean"]
    assert {r["report"]["stamps"]["host"] for r in runs} == {socket.gethostname()}


@pytest.mark.slow
def test_a_runtime_env_ray_cannot_set_up_is_one_line(bare_head: str, tmp_path: Path) -> None:
    done = _batch(tmp_path, "--ray-address", bare_head, "--ray-runtime-env",
                  '{"conda": "no-such-env"}')  # fmt: skip
    assert done.returncode == 2, done.stdout + done.stderr
    (line,) = done.stderr.splitlines()[1:]
    assert re.match(
        r"motiontool: error: Ray could not set up the runtime environment on [0-9.]+: ", line
    )
    assert "--ray-runtime-env" not in line, line  # no advice to pass what was passed


@pytest.mark.parametrize(
    ("given", "said"),
    [
        ('{"pip": [1,', "the JSON text: expected a JSON object"),
        ("[1]", "expected a JSON object such as"),
        ("missing.json", "cannot read 'missing.json': No such file or directory"),
    ],
)
def test_a_bad_runtime_env_is_one_line(tmp_path: Path, given: str, said: str) -> None:
    done = _batch(tmp_path, "--ray-runtime-env", given)
    assert done.returncode == 2
    assert len(done.stderr.splitlines()) == 1, done.stderr
    assert said in done.stderr


@pytest.mark.slow
def test_a_cluster_without_mujoco_is_one_line(one_ray: None, tmp_path: Path) -> None:
    """motiontool shipped, but the nodes' Python has no MuJoCo: the same one line."""
    folder = Path(tempfile.mkdtemp(prefix="mtenv"))
    try:
        python = python_without_motiontool(folder, hide=("mujoco",))
        with ray_cluster(nodes=1, python=python) as address:
            done = _batch(
                tmp_path, "--ray-address", address, "--ray-runtime-env", _shipped(tmp_path)
            )
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    assert done.returncode == 2, done.stdout + done.stderr
    error = done.stderr.splitlines()[-1]
    assert "cannot import motiontool or its simulation libraries (No module named 'mujoco'" in error
    assert error.endswith(
        "install motiontool[sim] in the cluster's image or pass --ray-runtime-env (docs/ray.md)"
    )
