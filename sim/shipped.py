"""Batch runs shipped as bytes, for workers on other machines (the Ray executor).

A worker on a cluster node cannot open the driver's paths: a relative path resolves against
the worker's folder, an absolute one names another machine's disk. So the driver packs each
:class:`~motiontool.sim.batch.RunSpec` as a :class:`Parcel` (:func:`pack`): the bytes of its
motion, of its chain's motions, of its robot's model file (a ``.urdf``/``.xml`` robot; a
built-in robot travels as its name and its model's sha256, checked on the worker), of its
world and the world's local PROTO files, and the driver's versions. The worker
(:func:`open_parcel`) refuses a parcel whose motiontool, MuJoCo or Pinocchio version is not its
own, writes the files in a temporary folder of its own, plays the run there, and returns a
:class:`Shipped`: the report (its paths the driver's again, its stamps the worker's, with its
host) and the bytes of every recording, each stored through ``store`` (Ray's object store).
The driver (:func:`land`) fetches the recordings one at a time and writes them where the
local pool would have, with the same atomic writes. Nothing here imports Ray.
"""

from __future__ import annotations

import os
import socket
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path
from typing import Any

from motiontool.errors import MotionToolError, OutputError
from motiontool.motionfmt.fileio import atomic_write, read_file, temporary_folder
from motiontool.sim.batch import RunSpec

__all__ = ["CHECKED", "Parcel", "Shipped", "land", "open_parcel", "pack"]

CHECKED = ("motiontool", "mujoco", "pinocchio")
"""The versions a worker must share with the driver (:func:`motiontool.stamps.stamps` names)."""

_MODEL_SUFFIXES = (".urdf", ".xml")


@dataclass(frozen=True)
class Parcel:
    """One run as the driver sends it.

    Attributes:
        spec: the run, its paths as the user gave them (the report names them so).
        files: (path as the run names it, absolute path on the driver, bytes) of every file
            the run reads.
        model_sha256: the model hash of a built-in robot (checked on the worker), else None.
        versions: the driver's versions of :data:`CHECKED`.
    """

    spec: RunSpec
    files: tuple[tuple[str, str, bytes], ...]
    model_sha256: str | None
    versions: tuple[tuple[str, str | None], ...]


@dataclass(frozen=True)
class Shipped:
    """What a worker returns: the run's report, and its recordings.

    Attributes:
        report: the runner's JSON report.
        artefacts: (file name, what ``store`` made of its bytes) of each recording.
        rrd_dir: the driver's folder of the recordings.
    """

    report: Any
    artefacts: tuple[tuple[str, Any], ...] = ()
    rrd_dir: str | None = None


def pack(task: Any) -> Any:
    """``task`` as a :class:`Parcel` when it is a :class:`RunSpec`, else as it is.

    Raises:
        MotionToolError: a file of the run cannot be read.
    """
    if not isinstance(task, RunSpec):
        return task
    options = dict(task.options)
    paths = [task.path, *task.chain]
    if task.robot.lower().endswith(_MODEL_SUFFIXES):
        paths.append(task.robot)
    if options.get("world"):
        paths += _world_files(str(options["world"]), options.get("robot_node"), task.robot)
    files = {p: (os.path.abspath(p), read_file(p)) for p in paths}
    shipped = tuple((p, at, data) for p, (at, data) in files.items())
    return Parcel(task, shipped, _model_sha256(task.robot), _versions())


@lru_cache(maxsize=64)
def _world_files(world: str, robot_node: str | None, robot: str) -> list[str]:
    """The world file and each local PROTO file its reading reads."""
    from motiontool.sim.world import read_world

    return [world, *(str(f) for f in read_world(world, robot_node, robot).files)]


@lru_cache(maxsize=64)
def _model_sha256(robot: str) -> str | None:
    from motiontool.kinematics.robots import AUTO, load_robot

    if robot == AUTO or robot.lower().endswith(_MODEL_SUFFIXES):
        return None
    return load_robot(robot).model_hash


@lru_cache(maxsize=1)
def _versions() -> tuple[tuple[str, str | None], ...]:
    from motiontool.stamps import stamps

    mine = stamps()
    return tuple((name, mine.get(name)) for name in CHECKED)


def open_parcel(runner: Callable[[Any], Any], parcel: Any, store: Callable[[bytes], Any]) -> Any:
    """Run ``parcel`` on this worker (a task that is no :class:`Parcel`: ``runner(parcel)``).

    Args:
        runner: the batch's runner (:func:`motiontool.sim.runs.run_spec`).
        store: what keeps a recording's bytes until the driver fetches them (``ray.put``).

    Raises:
        MotionToolError: this worker's versions are not the driver's, or its built-in robot's
            model is not the driver's; what the run raised, its paths the driver's.
    """
    if not isinstance(parcel, Parcel):
        return runner(parcel)
    _check_versions(parcel)
    with temporary_folder("motiontool-run-") as tmp:
        local, back = _materialise(parcel, Path(tmp))
        try:
            report = runner(local)
        except OutputError as exc:
            raise OutputError(_unmapped(str(exc), back)) from None
        except Exception as exc:
            raise MotionToolError(_unmapped(str(exc), back)) from None
        _check_model(parcel, report)
        report = _unmapped(report, back)
        if isinstance(report, dict) and isinstance(report.get("stamps"), dict):
            report["stamps"]["host"] = socket.gethostname()
        rrd = dict(local.options).get("rrd_dir")
        artefacts: tuple[tuple[str, Any], ...] = ()
        if rrd:
            found = sorted(Path(str(rrd)).iterdir())
            artefacts = tuple((f.name, store(f.read_bytes())) for f in found)
        return Shipped(report, artefacts, dict(parcel.spec.options).get("rrd_dir"))


def _check_versions(parcel: Parcel) -> None:
    mine = dict(_versions())
    for name, theirs in parcel.versions:
        if mine.get(name) != theirs:
            raise MotionToolError(
                f"worker {socket.gethostname()} has {name} {mine.get(name)}, the driver"
                f" {theirs}: install the driver's versions on the cluster (docs/ray.md)"
            )


def _check_model(parcel: Parcel, report: Any) -> None:
    """A built-in robot's model on the worker is the driver's (the report's model hash)."""
    if parcel.model_sha256 is None or not isinstance(report, dict):
        return
    found = (report.get("stamps") or {}).get("model_sha256")
    if found is not None and found != parcel.model_sha256:
        raise MotionToolError(
            f"worker {socket.gethostname()} has another model of robot {parcel.spec.robot!r}"
            f" (sha256 {found[:12]}, the driver's {parcel.model_sha256[:12]})"
        )


def _materialise(parcel: Parcel, tmp: Path) -> tuple[RunSpec, dict[str, str]]:
    """The parcel's files written below ``tmp``; its spec reading them; the worker's paths
    (as strings) -> the driver's, to give a report and a message the driver's paths again."""
    where: dict[str, str] = {}
    for path, at, data in parcel.files:
        local = tmp / "files" / at.lstrip(os.sep)  # the driver's layout: PROTOs beside worlds
        local.parent.mkdir(parents=True, exist_ok=True)
        local.write_bytes(data)
        where[path] = str(local)
    spec = parcel.spec

    def moved(p: str) -> str:
        return where[p]

    options = dict(spec.options)
    back = {moved(p): p for p in (spec.path, *spec.chain)}
    if options.get("world"):
        back[moved(str(options["world"]))] = str(options["world"])
        options["world"] = moved(str(options["world"]))
    if options.get("rrd_dir"):
        (tmp / "rrd").mkdir()
        back[str(tmp / "rrd")] = str(options["rrd_dir"])
        options["rrd_dir"] = str(tmp / "rrd")
    robot = spec.robot
    if robot.lower().endswith(_MODEL_SUFFIXES):
        back[moved(robot)] = robot
        robot = moved(robot)
    for path, worker_path in where.items():  # the PROTO files: the driver's absolute paths
        back.setdefault(worker_path, path)
    local_spec = replace(
        spec,
        path=moved(spec.path),
        chain=tuple(moved(p) for p in spec.chain),
        robot=robot,
        options=tuple(sorted(options.items())),
    )
    return local_spec, back


def _unmapped(value: Any, back: dict[str, str]) -> Any:
    """``value`` (JSON: dicts, lists, strings) with each worker path the driver's again."""
    if isinstance(value, str):
        for local in sorted(back, key=len, reverse=True):
            if local in value:
                value = value.replace(local, back[local])
        return value
    if isinstance(value, dict):
        return {k: _unmapped(v, back) for k, v in value.items()}
    if isinstance(value, list):
        return [_unmapped(v, back) for v in value]
    return value


def land(shipped: Any, fetch: Callable[[Any], bytes]) -> Any:
    """The report of ``shipped``, its recordings written on the driver one at a time
    (``fetch``: the bytes of what the worker stored, ``ray.get``), atomically; anything that is
    no :class:`Shipped` as it is.

    Raises:
        OutputError: a recording cannot be written.
    """
    if not isinstance(shipped, Shipped):
        return shipped
    for name, stored in shipped.artefacts:
        assert shipped.rrd_dir is not None, "a recording has its driver's folder"
        atomic_write(Path(shipped.rrd_dir) / name, fetch(stored))
    return shipped.report
