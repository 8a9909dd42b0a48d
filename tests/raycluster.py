"""Real Ray clusters for the tests, as ``ray start`` makes them: a head and worker nodes on
loopback, each started from a folder of its own, one CPU each; and a Python that has Ray and
the simulation's libraries but not motiontool (a cluster image without the package)."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import sysconfig
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["free_port", "python_without_motiontool", "ray_cluster"]

_RAY_MAIN = "import sys; from ray.scripts.scripts import main; sys.argv[0] = 'ray'; main()"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextmanager
def ray_cluster(nodes: int = 2, python: Path | None = None) -> Iterator[str]:
    """The address of a cluster of ``nodes`` nodes (a head and ``nodes - 1`` workers), its
    ``ray start`` run by ``python`` (its workers' Python; None: this one), stopped on exit. In a
    short folder of its own (Ray's sockets live under it, and a Unix socket's path holds at
    most 107 bytes: pytest's temporary folders under xdist are longer). Hold the ``one_ray``
    fixture: stopping it stops every Ray of the user."""
    ray = [str(python or sys.executable), "-c", _RAY_MAIN]
    temp = Path(tempfile.mkdtemp(prefix="mtray"))
    # Hermetic: `ray start` turns token auth on when it finds ~/.ray/auth_token (left by an earlier
    # local Ray); this cluster gets a home of its own, so it runs without auth like the driver.
    env = {**os.environ, "HOME": str(temp)}
    port = free_port()
    address = f"127.0.0.1:{port}"
    common = ["--node-ip-address=127.0.0.1", "--num-cpus=1", "--disable-usage-stats"]
    head = ["--head", f"--port={port}", "--include-dashboard=false", f"--temp-dir={temp}"]
    try:
        for node in range(nodes):
            folder = temp / f"node{node}"
            folder.mkdir()
            how = head if node == 0 else [f"--address={address}"]
            subprocess.run(
                [*ray, "start", *how, *common],
                check=True, capture_output=True, timeout=120, env=env, cwd=folder,
            )  # fmt: skip
        yield address
    finally:
        subprocess.run([*ray, "stop", "--force"], capture_output=True, timeout=120, env=env)
        shutil.rmtree(temp, ignore_errors=True)


def python_without_motiontool(folder: Path, hide: tuple[str, ...] = ()) -> Path:
    """A virtual environment in ``folder`` whose Python imports this one's packages (Ray,
    MuJoCo, NumPy...) but not motiontool (this checkout is installed in editable mode, through
    a ``.pth`` file that a path added by another ``.pth`` file does not run), nor the packages
    ``hide`` names (each entry of this site-packages linked in a folder of its own, but
    theirs); its python."""
    subprocess.run(
        [sys.executable, "-m", "venv", "--without-pip", str(folder)], check=True, timeout=120
    )
    ours = Path(sysconfig.get_paths()["purelib"])
    if hide:
        view = folder / "view"
        view.mkdir()
        for entry in ours.iterdir():
            if not entry.name.lower().startswith(hide):
                (view / entry.name).symlink_to(entry)
        ours = view
    (theirs,) = (folder / "lib").glob("python3*/site-packages")
    (theirs / "ours.pth").write_text(f"{ours}\n")
    python = folder / "bin" / "python"
    names = ("motiontool", *hide)
    code = f"import ray\nfor n in {names!r}:\n try: __import__(n)\n except ImportError: print(n)"
    probe = subprocess.run(
        [str(python), "-c", code], capture_output=True, text=True, timeout=120, cwd=folder
    )
    assert probe.stdout.split() == list(names), probe.stdout + probe.stderr
    return python
