"""Batch simulation: many files x robots x perturbation samples, cached, on a pool or a Ray cluster.

The plan is a list of :class:`RunSpec` (pure data, picklable). A *runner* turns one spec into a
JSON-able report (``motiontool.sim.runs.run_spec`` plays it in MuJoCo); the executors
(:mod:`motiontool.sim.executor`: a local pool or Ray, one protocol, one ``Outcome``) only move
specs and reports around, so the local pool and Ray give identical results for the same seed.
Results are cached on disk by (file content, model hash, options, perturbation, tool version):
an interrupted or repeated batch only runs what is missing. A run's expectations
(:mod:`motiontool.sim.expect`) are not part of the key: the raw report is cached and judged
after the cache, so changing an expectation re-judges without re-running. A cached run whose
outputs (its recording) are missing is run again.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import random
import time
from collections.abc import Callable, Generator, Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from motiontool import __version__
from motiontool.disk_cache import (
    BYTES_PER_MB,
    ResultCache,
    cache_root,
)
from motiontool.disk_cache import (
    code_stamp as disk_code_stamp,
)
from motiontool.errors import MotionToolError, OutputError
from motiontool.kinematics.robots import AUTO, pick_robot, resolve_robot
from motiontool.motionfmt.fileio import read_file
from motiontool.motionfmt.reader import read_bytes
from motiontool.sim.batch_results import CACHED_STATUSES, BatchResult, RunResult, RunStatus
from motiontool.sim.executor import MAX_TIMEOUT_S, Outcome, get_executor
from motiontool.sim.expect import parse_expectations
from motiontool.sim.perturb import PERTURBATIONS, Perturbation, PerturbationKind, parse_perturbation
from motiontool.sim.sidecar import Sidecar
from motiontool.sim.start import StartState

if TYPE_CHECKING:
    from motiontool.sim.session import MotionPlan

__all__ = [
    "DEFAULT_MAX_BYTES",
    "DEFAULT_MAX_MB",
    "PERTURBATIONS",
    "BatchResult",
    "Perturbation",
    "PerturbationKind",
    "RunResult",
    "RunSpec",
    "RunStatus",
    "check_robots",
    "default_cache_dir",
    "draw",
    "parse_perturbation",
    "plan",
    "plan_batch",
    "recording_stems",
    "run_batch",
]

DEFAULT_MAX_MB = 500
"""The size batch's result cache (:class:`motiontool.disk_cache.ResultCache`) is pruned to
after a batch, in MB (a Nao run's report is about 10 kB)."""
DEFAULT_MAX_BYTES = DEFAULT_MAX_MB * BYTES_PER_MB
""":data:`DEFAULT_MAX_MB` in bytes."""


def default_cache_dir() -> Path:
    """``$XDG_CACHE_HOME/motiontool/batch`` (``~/.cache/motiontool/batch``)."""
    return cache_root() / "batch"


@dataclass(frozen=True)
class RunSpec:
    """One simulation run: a motion file on a robot with one sample of perturbations.

    Attributes:
        path: the motion file as the user named it.
        content_sha256: hash of the file's bytes (the cache key uses content, not the path).
        robot: robot spec string (``nao``, ``ur5e``, a model path, ``erd:<name>``); ``auto``
            only for a file no built-in robot fits (the run fails, saying why).
        sample: sample index (0 = nominal when no perturbation is given).
        params: perturbation values of this sample, name -> value (units in PERTURBATIONS).
        options: play options (time step in ms, loops, reverse, start pose, ...).
        expect: expectations the run must meet (``dx>=0.3``, ``upright``; not in the cache
            key: judged on the report after the cache).
        chain, chain_sha256: the motions played before it, first first (its sidecar's
            ``after``: the run is a chain), and the hashes of their bytes (in the cache key).
    """

    path: str
    content_sha256: str
    robot: str
    sample: int = 0
    params: tuple[tuple[str, float], ...] = ()
    options: tuple[tuple[str, Any], ...] = ()
    expect: tuple[str, ...] = ()
    chain: tuple[str, ...] = ()
    chain_sha256: tuple[str, ...] = ()

    @property
    def shown(self) -> str:
        """The motion, or every element of its chain: ``Walk_Start.motion + Walk_Loop.motion``."""
        return " + ".join((*self.chain, self.path))

    @property
    def label(self) -> str:
        extra = ", ".join(f"{k}={v:.4g}" for k, v in self.params)
        return f"{self.shown} [{self.robot}" + (f" #{self.sample}: {extra}]" if extra else "]")

    def cache_key(self, model_hash: str, code: str = "") -> str:
        """The run's key in the result cache: everything its report depends on, ``code``
        (:func:`code_stamp`) the simulation code and libraries that compute it."""
        doc = {
            "content": self.content_sha256,
            "model": model_hash,
            "code": code,
            "robot": self.robot,
            "params": list(self.params),
            "options": list(self.options),
            "tool": __version__,
            **({"chain": list(self.chain_sha256)} if self.chain_sha256 else {}),
        }
        return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()


@functools.cache
def code_stamp() -> str:
    """What changes when the code that plays and measures a run changes: the package's files
    (path, size, modification time: an edit, an upgrade) and where MuJoCo, Pinocchio, coal and
    numpy are installed. A cached report made by other code is never served, version or not."""
    folders = ("motionfmt", "kinematics", "sim")
    return disk_code_stamp(folders, ("numpy", "mujoco", "pinocchio", "coal"))


def check_robots(robots: Sequence[str]) -> None:
    """Load each robot of ``robots`` but ``auto`` once: a bad name fails before anything runs.

    Raises:
        UnknownRobotError: a name that is no robot (its choices include ``auto``).
        MotionToolError: a model file that is missing or that Pinocchio cannot read.
    """
    for name in dict.fromkeys(robots):
        if name != AUTO:
            resolve_robot(name)


def plan(
    files: Sequence[str | Path],
    robots: Sequence[str],
    *,
    perturbations: Sequence[Perturbation] = (),
    samples: int = 1,
    seed: int = 0,
    options: dict[str, Any] | None = None,
    expect: Sequence[str] = (),
) -> list[RunSpec]:
    """Every (file, robot, sample) run, with seeded perturbation draws.

    ``robots`` are names for :func:`motiontool.kinematics.resolve_robot` (not loaded here:
    :func:`check_robots` checks them once): ``auto`` becomes, per file, the built-in robot its
    joints fit; a file no robot fits keeps ``auto``, and its run
    fails alone, saying why (the others still run). Draws depend only on ``seed``, the sample
    index and the perturbation names, so the same command plans the same runs on any executor.
    Without perturbations one sample is run.

    Raises:
        MotionToolError: a file that cannot be read, or ``samples`` < 1.
    """
    if samples < 1:
        raise MotionToolError(f"samples must be >= 1, got {samples}")
    if not perturbations:
        samples = 1
    opts = tuple(sorted((options or {}).items()))
    specs = []
    for raw in files:
        data = read_file(raw)
        digest = hashlib.sha256(data).hexdigest()
        detected = AUTO
        if AUTO in robots:
            found = pick_robot(AUTO, read_bytes(data, str(raw)).joints)
            detected = AUTO if found is None else found.name
        for robot in (detected if r == AUTO else r for r in robots):
            for k in range(samples):
                params = draw(perturbations, seed, k)
                specs.append(RunSpec(str(raw), digest, robot, k, params, opts, tuple(expect)))
    return specs


def draw(
    perturbations: Sequence[Perturbation], seed: int, sample: int
) -> tuple[tuple[str, float], ...]:
    """The values of sample ``sample`` (name, value; by name; units in :data:`PERTURBATIONS`),
    uniform in each range, seeded by ``seed`` and ``sample`` alone (``batch --perturb``'s draws,
    and ``--robustness``'s members: :mod:`motiontool.sim.robustness`)."""
    rng = random.Random(f"{seed}:{sample}")
    return tuple(
        (p.name, rng.uniform(p.low, p.high)) for p in sorted(perturbations, key=lambda p: p.name)
    )


def plan_batch(
    files: Sequence[Path],
    robots: Mapping[Path, Sequence[str]],
    *,
    options: Mapping[str, Any],
    timesteps: Mapping[Path, int | None],
    expect: Sequence[str] = (),
    start: StartState | str | None = None,
    sidecar: bool = True,
    roots: Sequence[Path] = (),
    rrd_dir: Path | None = None,
    perturbations: Sequence[Perturbation] = (),
    samples: int = 1,
    seed: int = 0,
    after: Path | None = None,
) -> list[RunSpec]:
    """Every run of a batch (:func:`plan`), file by file, each with what its sidecar and the
    caller ask of it (:func:`motiontool.sim.session.plan_motion`: the sidecar's expectations,
    then ``expect``; ``start`` or the sidecar's; its ``after`` or ``after``), and its recording.

    Args:
        robots: the robots each file is played on; timesteps: each file's control step, ms
            (None: the robot's).
        options: play options of every run (:func:`plan`); a lying start is added per file.
        sidecar: read each motion's sidecar; roots: the batch's folders, where the search for
            a sidecar stops (:func:`motiontool.sim.sidecar.search_boundary`).
        rrd_dir: the folder of the runs' recordings (None: none), not made here: the caller
            makes it once it has checked the plan (no report where a recording goes).

    Raises:
        ExpectationError: an expectation of ``expect`` does not parse (before any sidecar is
            read); SidecarError: a sidecar cannot be used; MotionToolError: a file cannot be
            read, ``after`` is no motion Webots plays.
    """
    from motiontool.sim.play import read_playable
    from motiontool.sim.session import plan_motion

    parse_expectations(expect)
    if after is not None:
        read_playable(after)  # a motion Webots would reject: its file:line before any run
    rrd_names = recording_stems(files)
    sidecars: dict[Path, Sidecar] = {}
    specs = []
    for f in files:
        motion = plan_motion(
            f, expect, start=start, sidecar=sidecar, roots=roots, cache=sidecars, after=after
        )
        recording = None if rrd_dir is None else (rrd_dir, rrd_names[str(f)])
        file_options = _file_options(options, timesteps[f], motion, recording)
        runs = plan(
            [f],
            robots[f],
            perturbations=perturbations,
            samples=samples,
            seed=seed,
            options=file_options,
            expect=motion.expect,
        )
        specs += [_chained(run, motion.before) for run in runs]
    return specs


def _file_options(
    options: Mapping[str, Any],
    timestep_ms: int | None,
    motion: MotionPlan,
    recording: tuple[Path, str] | None,
) -> dict[str, Any]:
    """A file's play options: ``options``, its step (ms), lying start, world, chain, recording."""
    file_options = {**options, "timestep_ms": timestep_ms}
    if motion.start is not None and motion.start.lying:
        file_options["start"] = str(motion.start)
    if motion.world is not None:  # the sidecar's world (cli.batch adds its hash)
        file_options.update(world=str(motion.world), robot_node=motion.robot_node)
    if recording is not None:
        file_options.update(rrd_dir=str(recording[0]), rrd_name=recording[1])
    if motion.before:
        file_options["chain"] = True
    return file_options


def _chained(spec: RunSpec, before: Sequence[Path]) -> RunSpec:
    """``spec`` played after the motions ``before`` (a sidecar's ``after``: a chain)."""
    hashes = tuple(hashlib.sha256(read_file(p)).hexdigest() for p in before)
    return replace(spec, chain=tuple(str(p) for p in before), chain_sha256=hashes)


def recording_stems(files: Sequence[str | Path]) -> dict[str, str]:
    """A name per motion file for its recordings (``<name>.<robot>.<sample>.rrd``), unique
    among ``files``: the file's stem (``wave``) where no other file has it, else its path below
    the common folder of the files that share it, folders joined with ``-`` (``a-wave`` and
    ``b-wave`` for ``a/wave.motion`` and ``b/wave.motion``). Names are compared without case
    (a case-insensitive file system would merge ``Wave`` and ``wave``); a name still taken gets
    a short hash of the file's absolute path. Keys are the paths as given (``str(path)``).
    """
    paths = list(dict.fromkeys(str(f) for f in files))
    by_stem: dict[str, list[str]] = {}
    for p in paths:
        by_stem.setdefault(Path(p).stem.casefold(), []).append(p)
    names: dict[str, str] = {}
    for group in by_stem.values():
        if len(group) == 1:
            names[group[0]] = Path(group[0]).stem
            continue
        absolute = [os.path.abspath(p) for p in group]
        root = os.path.commonpath([os.path.dirname(a) for a in absolute])
        for p, a in zip(group, absolute, strict=True):
            parts = Path(os.path.relpath(a, root)).with_suffix("").parts
            names[p] = "-".join(parts)
    taken: dict[str, int] = {}
    for name in names.values():
        taken[name.casefold()] = taken.get(name.casefold(), 0) + 1
    for p, name in names.items():
        if taken[name.casefold()] > 1:
            digest = hashlib.sha256(os.path.abspath(p).encode()).hexdigest()[:8]
            names[p] = f"{name}-{digest}"
    return names


def _verdict(spec: RunSpec, report: dict[str, Any], wall_s: float, cached: bool) -> RunResult:
    """``clean`` or ``failed``, as ``report`` says (its ``clean`` and ``reason``)."""
    clean = bool(report.get("clean"))
    why = "" if clean else str(report.get("reason") or "not clean")
    return RunResult(spec, "clean" if clean else "failed", why, report, wall_s, cached)


def _classify(spec: RunSpec, outcome: Outcome) -> RunResult:
    """The result of the run of ``spec`` that ended as ``outcome``.

    Raises:
        OutputError: the run could not write a file it writes (``unwritten``).
    """
    if outcome.status == "done":
        return _verdict(spec, outcome.value, outcome.wall_s, cached=False)
    if outcome.status == "unwritten":
        raise OutputError(outcome.reason)
    return RunResult(spec, outcome.status, outcome.reason, None, outcome.wall_s)


def _judged(result: RunResult) -> RunResult:
    """``result`` with its spec's expectations judged on its report (runs without a report,
    or without expectations, are returned as they are)."""
    if not result.spec.expect or result.report is None or result.status not in CACHED_STATUSES:
        return result
    from motiontool.sim.expect import apply_expectations

    report = apply_expectations(result.report, result.spec.expect)
    return _verdict(result.spec, report, result.wall_s, result.cached)


def _load(cache: ResultCache | None, spec: RunSpec, key: str) -> RunResult | None:
    doc = cache.load(key) if cache is not None else None
    if doc is None or doc.get("status") not in CACHED_STATUSES:
        return None
    return RunResult(spec, doc["status"], doc.get("reason", ""), doc.get("report"), 0.0, True)


def _store(cache: ResultCache | None, result: RunResult, key: str) -> None:
    if cache is not None and result.status in CACHED_STATUSES:
        payload = {"status": result.status, "reason": result.reason, "report": result.report}
        cache.store(key, payload)


def run_batch(
    specs: Sequence[RunSpec],
    runner: Callable[[RunSpec], dict[str, Any]],
    *,
    model_hash: Callable[[str], str],
    executor: str = "local",
    jobs: int = 2,
    timeout_s: float | None = None,
    cache_dir: Path | None = None,
    cache_max_bytes: int | None = DEFAULT_MAX_BYTES,
    ray_address: str | None = None,
    outputs: Callable[[RunSpec], Sequence[Path]] | None = None,
    progress: Callable[[RunResult, int, int], None] | None = None,
    spool_dir: Path | None = None,
) -> BatchResult:
    """Run ``specs`` (cached ones are not run again) and return every result in plan order.

    Args:
        runner: a picklable module-level function returning a JSON-able report with at least
            ``clean`` (bool) and ``reason`` (str).
        model_hash: robot spec -> model hash, for the cache key.
        executor: ``local`` (a process pool on this machine) or ``ray``
            (:func:`motiontool.sim.executor.get_executor`).
        jobs: parallel runs (local workers, or Ray tasks in flight).
        timeout_s: wall-clock limit of one run in seconds.
        cache_dir: where results are cached; None disables the cache.
        cache_max_bytes: the cache is pruned to this size (bytes) after the batch, least
            recently used results first
            (:class:`motiontool.disk_cache.ResultCache`); None: no limit.
        ray_address: Ray cluster address (``auto``, ``ray://...``); None starts a local one.
        outputs: the files a run writes besides its report (its recording,
            :func:`motiontool.sim.runs.run_outputs`): a cached run one of whose files is
            missing is run again.
        progress: called after every run with (result, runs done, runs total).
        spool_dir: an empty folder where each run's report is stored as it ends, and read
            back when a report of the batch needs it (:meth:`RunResult.full_report`), so that
            a batch of any number of runs holds none of their reports; None: held.

    Raises:
        OutputError: a run could not write a file it writes (its recording on a full disk):
            the batch stops, its runs still going are stopped.
    """
    _check_timeout(timeout_s)
    t0 = time.monotonic()
    run = get_executor(executor, ray_address=ray_address)
    cache = None if cache_dir is None else ResultCache(cache_dir, cache_max_bytes)
    code = code_stamp()
    keys = [s.cache_key(model_hash(s.robot), code) for s in specs]
    results = _Results(len(specs), progress, spool_dir)
    hits = [_cached(cache, spec, key, outputs) for spec, key in zip(specs, keys, strict=True)]
    todo = [i for i, hit in enumerate(hits) if hit is None]
    for i, hit in enumerate(hits):
        if hit is not None:
            results.finish(i, hit)
    outcomes = run(runner, [specs[i] for i in todo], jobs=jobs, timeout_s=timeout_s)
    _collect(outcomes, [(i, specs[i], keys[i]) for i in todo], cache, results)
    if cache is not None:
        cache.prune()
    models = {s.robot: model_hash(s.robot) for s in specs}
    models = {robot: sha for robot, sha in sorted(models.items()) if sha}  # auto: none fits
    return BatchResult(results.in_plan_order(), time.monotonic() - t0, executor, jobs, models)


def _collect(
    outcomes: Iterator[Outcome],
    todo: list[tuple[int, RunSpec, str]],
    cache: ResultCache | None,
    results: _Results,
) -> None:
    """Each outcome of the runs ``todo`` (their index in the plan, spec and cache key, in the
    order given to the executor) classified, cached and kept in ``results``.

    Raises:
        OutputError: a run could not write a file it writes: the runs still going are stopped
            (the executor's generator closed) and the batch stops.
    """
    try:
        for outcome in outcomes:
            i, spec, key = todo[outcome.index]
            try:
                result = _classify(spec, outcome)
            except OutputError as exc:
                at = f"the batch stopped at run {results.done + 1} of {len(results)}"
                raise OutputError(f"{exc} ({at})") from None
            _store(cache, result, key)
            results.finish(i, result)
    finally:
        if isinstance(outcomes, Generator):  # a batch that stops stops its runs now
            outcomes.close()


class _Results:
    """The results of a batch as they come (cached first, then as runs end), each judged on its
    expectations, its report stored in ``spool`` (if given), and told to ``progress`` with
    the count done."""

    def __init__(
        self,
        total: int,
        progress: Callable[[RunResult, int, int], None] | None,
        spool: Path | None = None,
    ):
        self._results: list[RunResult | None] = [None] * total
        self._done = 0
        self._progress = progress
        self._spool = spool

    def finish(self, i: int, result: RunResult) -> None:
        """``result`` is the result of run ``i``: judged, kept, and told."""
        judged = _judged(result)
        if self._spool is not None and judged.report is not None:
            path = self._spool / f"{i}.json"
            path.write_text(json.dumps(judged.report), encoding="ascii")  # exact: NaN, \udcxx
            judged = replace(judged, report=None, stored=path)
        self._results[i] = judged
        self._done += 1
        if self._progress:
            self._progress(judged, self._done, len(self._results))

    @property
    def done(self) -> int:
        """How many runs have a result."""
        return self._done

    def __len__(self) -> int:
        """How many runs the batch has."""
        return len(self._results)

    def in_plan_order(self) -> list[RunResult]:
        """Every result, in plan order (each run has one by now)."""
        final = [r for r in self._results if r is not None]
        assert len(final) == len(self._results), "every run has a result"
        return final


def _check_timeout(timeout_s: float | None) -> None:
    """A run's timeout (s) is None or in (0, :data:`MAX_TIMEOUT_S`]."""
    if timeout_s is not None and not 0 < timeout_s <= MAX_TIMEOUT_S:
        raise MotionToolError(
            f"a run's timeout must be in (0, {MAX_TIMEOUT_S:g}] s, got {timeout_s}"
        )


def _cached(
    cache: ResultCache | None,
    spec: RunSpec,
    key: str,
    outputs: Callable[[RunSpec], Sequence[Path]] | None,
) -> RunResult | None:
    """The cached result of ``spec``, or None: not cached, or a file it writes is missing."""
    return _load(cache, spec, key) if _outputs_exist(spec, outputs) else None


def _outputs_exist(spec: RunSpec, outputs: Callable[[RunSpec], Sequence[Path]] | None) -> bool:
    return outputs is None or all(path.exists() for path in outputs(spec))
