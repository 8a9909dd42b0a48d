"""A play session: what a motion's sidecar and the caller ask of a run, then the run, judged.

``motiontool play`` and ``motiontool batch`` parse their options and render what this module
returns; the plumbing between (sidecar, expectations, start state, reading, robot, stamps,
judging) is here, once:

- :func:`plan_motion` joins what a motion's ``motions.toml`` sidecar says about it
  (:mod:`motiontool.sim.sidecar`) with the expectations and start state the caller gives: the
  sidecar's expectations first, then the given ones; the given start beats the sidecar's. A bad
  expectation or sidecar raises before anything runs. ``batch`` plans each of its files with it
  (:func:`motiontool.sim.batch.plan_batch`).
- :func:`plan_play` plans a ``play`` of one or more files (a sidecar describes one motion: it is
  read when one file, not standard input, is played), and :meth:`PlayPlan.run` plays it
  (:func:`motiontool.sim.play.play`) and judges the expectations on the report
  (:func:`motiontool.sim.expect.evaluate`). A run that cannot start (a file Webots rejects, no
  robot, a bad option) comes back as a :class:`PlayResult` with its ``error``: its JSON is the
  report of a run that could not start, and its recording (when asked for) says why.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from motiontool import exit_codes
from motiontool.errors import MotionToolError
from motiontool.kinematics.robots import AUTO, resolve_robot
from motiontool.motionfmt.fileio import is_stdin, source_name
from motiontool.sim.bag import BagTarget
from motiontool.sim.expect import Expectation, evaluate, parse_expectations
from motiontool.sim.live import LiveView
from motiontool.sim.play import PlayOptions, Progress, play, read_playable
from motiontool.sim.report import SCHEMA, SCHEMA_VERSION, PlayReport
from motiontool.sim.sidecar import Sidecar, SidecarEntry, after_path, lookup
from motiontool.sim.start import StartState
from motiontool.sim.world import read_world
from motiontool.sim.world_run import WorldRun, world_run
from motiontool.stamps import stamps

__all__ = ["MotionPlan", "PlayPlan", "PlayResult", "plan_motion", "plan_play"]

NOT_STARTED_EXIT_CODE = exit_codes.ERROR
"""The exit code a run that could not start reports (a usage or input error)."""


@dataclass(frozen=True)
class MotionPlan:
    """What a run of one motion must do, and how it starts.

    Attributes:
        expect: the expectations as written: the sidecar's (in file order), then the given ones.
        expectations: the same, parsed.
        start: the given start state, else the sidecar's, else None (not set: standing).
        world, robot_node: the sidecar's Webots world and its robot node (None: not set).
        before: the motions played before it, first first: the chain its sidecar's ``after``
            makes (followed back, each motion's own sidecar's ``after``); empty: none.
    """

    expect: tuple[str, ...]
    expectations: tuple[Expectation, ...]
    start: StartState | None
    world: Path | None = None
    robot_node: str | None = None
    before: tuple[Path, ...] = ()


def plan_motion(
    motion: str | Path,
    expect: Sequence[str] = (),
    *,
    start: StartState | str | None = None,
    sidecar: bool = True,
    roots: Sequence[Path] = (),
    cache: dict[Path, Sidecar] | None = None,
    after: Path | None = None,
) -> MotionPlan:
    """What ``motion``'s sidecar and the caller (``expect``, ``start``, ``after``) ask of its run.

    Args:
        sidecar: read the motion's sidecar (False: only what is given applies).
        after: the motion played before it where its sidecar has no ``after`` (``batch
            --after``), itself after what its own sidecar's ``after`` names.
        roots, cache: as for :func:`motiontool.sim.sidecar.lookup` (a batch's folders; parsed
            sidecars kept between motions).

    Raises:
        SidecarError: the sidecar cannot be used. ExpectationError: an expectation does not
            parse. MotionToolError: ``start`` is no start state.
    """
    entry = lookup(motion, tuple(roots), cache) if sidecar else None
    expected = (entry.expect if entry else ()) + tuple(expect)
    before = _before(motion, entry, tuple(roots), cache)
    if not before and after is not None:
        previous = lookup(after, tuple(roots), cache) if sidecar else None
        before = (*_before(after, previous, tuple(roots), cache), after)
    if start is not None:
        chosen: StartState | str | None = start
    elif before:  # a chain starts as its first motion does
        first = lookup(before[0], tuple(roots), cache) if sidecar else None
        chosen = first.start if first else None
    else:
        chosen = entry.start if entry else None
    return MotionPlan(
        expected,
        tuple(parse_expectations(expected)),
        None if chosen is None else StartState.parse(chosen),
        entry.world if entry else None,
        entry.robot_node if entry else None,
        before,
    )


MAX_CHAIN = 64
"""Most motions a sidecar's ``after`` chain may hold (a longer one is most likely a loop)."""


def _before(
    motion: str | Path,
    entry: SidecarEntry | None,
    roots: tuple[Path, ...],
    cache: dict[Path, Sidecar] | None,
) -> tuple[Path, ...]:
    """The motions played before ``motion``, first first, following each one's sidecar
    ``after`` back (:func:`motiontool.sim.sidecar.after_path`).

    Raises:
        SidecarError: an ``after`` that names no motion file. MotionToolError: a chain that
            comes back to a motion it holds, or longer than :data:`MAX_CHAIN`.
    """
    chain: list[Path] = []
    seen = {Path(motion).resolve()}
    current: str | Path = motion
    while entry is not None and entry.after is not None:
        previous = after_path(entry, current)
        if previous.resolve() in seen or len(chain) >= MAX_CHAIN:
            names = " <- ".join(p.stem for p in [Path(motion), *reversed(chain), previous])
            raise MotionToolError(f"{entry.path}: the after chain {names} comes back on itself")
        seen.add(previous.resolve())
        chain.append(previous)
        current, entry = previous, lookup(previous, roots, cache)
    return tuple(reversed(chain))


@dataclass
class PlayResult:
    """A play session's outcome: the report, or the error that stopped the run before it could
    start.

    Attributes:
        files: the motion files as given (``-``: standard input).
        stamps: the versions the report is stamped with (the model hash once the robot is
            known; :func:`motiontool.stamps.stamps`).
        report: the judged report (None when the run could not start).
        error: why the run could not start (None when it ran).
    """

    files: list[Path]
    stamps: dict[str, Any]
    report: PlayReport | None = None
    error: MotionToolError | None = None

    @property
    def exit_code(self) -> int:
        """The report's exit code (0 clean, 1 not clean), 2 when the run could not start."""
        return self.report.exit_code if self.report is not None else NOT_STARTED_EXIT_CODE

    def to_json(self) -> dict[str, Any]:
        """The report as JSON (``motiontool.play``); for a run that could not start, the stamps,
        the files, ``clean`` false, ``exit_code`` 2 and the error as ``reason`` and ``error``."""
        if self.report is not None:
            return self.report.to_json()
        message = str(self.error)
        return {
            "schema": SCHEMA,
            "schema_version": SCHEMA_VERSION,
            "stamps": self.stamps,
            "files": [{"path": source_name(f)} for f in self.files],
            "clean": False,
            "exit_code": NOT_STARTED_EXIT_CODE,
            "reason": message,
            "error": message,
        }


@dataclass(frozen=True)
class PlayPlan:
    """A planned ``play``: its files, what the run must do and how it starts, and the Webots
    world it plays in, if any (:func:`plan_play`).

    Attributes:
        world: a Webots world file the run takes its settings from
            (:func:`motiontool.sim.world.read_world`), read when the robot is known; None: none.
        robot_node: the name or DEF of the world's robot node that plays (None: the world's
            one robot of the motion's kind).
    """

    files: tuple[Path, ...]
    motion: MotionPlan
    world: Path | None = None
    robot_node: str | None = None

    @property
    def start(self) -> StartState:
        """The start state of the run: the plan's, else standing."""
        return self.motion.start or StartState.STANDING

    def run(
        self,
        *,
        robot: str = AUTO,
        options: PlayOptions | None = None,
        rrd: Path | None = None,
        bag: Path | BagTarget | None = None,
        progress: Progress | None = None,
        live: LiveView | None = None,
    ) -> PlayResult:
        """Read the files, resolve ``robot`` on their joints, play them with ``options`` (its
        ``start`` replaced by the plan's), judge the expectations on the report.

        Args:
            robot: a name for :func:`motiontool.kinematics.resolve_robot` (``auto``: the
                built-in robot the joints of all the files fit).
            rrd: write a Rerun recording there, also when the run could not start (then it
                holds the stamps and the error).
            bag: write a ROS 2 bag of the run there (:mod:`motiontool.sim.bag`), when it ran.
            progress: told how far the run is (:func:`motiontool.sim.play.play`).
            live: show the run live (:mod:`motiontool.sim.live`); a viewer that goes away
                raises :class:`~motiontool.sim.live.ViewerClosed`.

        Returns:
            The result; a :class:`MotionToolError` before the simulation starts (a file Webots
            rejects, no robot, a bad option) is its ``error``, not raised.
        """
        result = PlayResult(list(self.files), dict(stamps()))
        opts = replace(options or PlayOptions(), start=self.start)
        try:
            motions = [read_playable(f) for f in self.files]  # read once: play() takes them
            spec = resolve_robot(robot, (j for m in motions for j in m.joints))
            result.stamps = dict(stamps(spec.model_hash))
            in_world = self._world(spec.name)
            names = [str(f) for f in self.files]
            report = play(
                motions,
                names=names,
                robot=spec,
                options=opts,
                rrd=rrd,
                stamps=result.stamps,
                bag=bag,
                progress=progress,
                world=in_world,
                live=live,
            )
            report.expectations = evaluate(self.motion.expectations, report)
        except MotionToolError as exc:
            result.error = exc
            if rrd is not None:
                self._write_failure(rrd, exc, result.stamps)
            return result
        result.report = report
        return result

    def _world(self, robot: str) -> WorldRun | None:
        """The world the run plays in: the one given, else the sidecar's (each with its robot
        node), else None."""
        world, node = self.world, self.robot_node
        if world is None:
            world, node = self.motion.world, self.motion.robot_node
        return None if world is None else world_run(read_world(world, node, robot))

    def _write_failure(self, rrd: Path, error: MotionToolError, doc_stamps: dict[str, Any]) -> None:
        """The recording of a run that could not start: the stamps and the error."""
        from motiontool.sim.recording import write_failure

        props = {k: "" if v is None else str(v) for k, v in doc_stamps.items()}
        write_failure(rrd, str(error), props, " + ".join(f.name for f in self.files))


def plan_play(
    files: Sequence[Path],
    *,
    expect: Sequence[str] = (),
    start: StartState | str | None = None,
    sidecar: bool = True,
    world: Path | None = None,
    robot_node: str | None = None,
) -> PlayPlan:
    """Plan playing ``files`` one after another with the expectations ``expect`` and the start
    state ``start`` (None: the sidecar's, else standing), in the Webots ``world`` (its robot
    node ``robot_node``; see :class:`PlayPlan`). A sidecar describes one motion: it is read
    (``sidecar``) only when one file, not standard input, is played; its ``after`` makes the
    run a chain, the motions played before it first (:attr:`MotionPlan.before`).

    Raises:
        MotionToolError: no file; a sidecar, an expectation or a start that cannot be used
            (see :func:`plan_motion`): before anything runs.
    """
    if not files:
        raise MotionToolError("no motion file to play")
    one_file = len(files) == 1 and not is_stdin(files[0])
    motion = plan_motion(files[0], expect, start=start, sidecar=sidecar and one_file)
    return PlayPlan((*motion.before, *files), motion, world, robot_node)
