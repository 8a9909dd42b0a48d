"""How sure a verdict is: ``--robustness N`` replays a run over N perturbed members.

A run's verdicts are its *clean* verdict (no fall, no collision, no simulator warning, no
error: the run's problems other than its expectations) and one per expectation. Each member is
the same run with one draw of :data:`ENSEMBLE` (the ``batch --perturb`` perturbations of
:data:`motiontool.sim.batch.PERTURBATIONS`, drawn by :func:`motiontool.sim.batch.draw`) and a
physics step of :data:`PHYSICS_STEPS_MS` that divides the run's control step (in a Webots
world, its basicTimeStep). A member is a :class:`~motiontool.sim.batch.RunSpec`: it runs on the
batch executors and is cached as a batch run is. Each verdict is then (:func:`judge`):

- ``holds``: the nominal run passes it and every member agrees;
- ``fragile``: the nominal run passes it, k of the n members do not (named, with their values);
- ``fails``: the nominal run does not pass it.

Why these bounds are plausible physics (docs/simulation.md, *Robustness*; the sweep of
docs/fidelity.md): the floor friction of the Webots walks is not known better than a factor of
2 either way (μ 0.5 to 2 keeps Forwards50, TurnLeft60 and TaiChi walking at 1 to 4 ms), a
physics step of 1 to 4 ms is where MuJoCo's integration converges (10 and 20 ms are where the
walks fall for numerical, not physical, reasons), the masses of a Nao's parts within 5 %, its
placement within 5 degrees of heading and its joints' start within 0.01 rad (about the
calibration of its encoders).
"""

from __future__ import annotations

import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Literal

from motiontool.errors import MotionToolError
from motiontool.sim.perturb import Perturbation

if TYPE_CHECKING:
    from motiontool.sim.batch import RunSpec
    from motiontool.sim.batch_results import BatchResult, RunResult
    from motiontool.sim.report import PlayReport

__all__ = [
    "DEFAULT_MEMBERS",
    "ENSEMBLE",
    "PHYSICS_STEPS_MS",
    "Disagreement",
    "Robustness",
    "Verdict",
    "VerdictStatus",
    "describe",
    "judge",
    "member_specs",
    "physics_steps",
    "regroup",
    "with_members",
]

DEFAULT_MEMBERS = 8
"""The ensemble size docs/play.md and ``--help`` suggest (``--robustness 8``)."""

ENSEMBLE: tuple[Perturbation, ...] = (
    Perturbation("friction", 0.5, 2.0),
    Perturbation("mass", 0.95, 1.05),
    Perturbation("start-yaw", -5.0, 5.0),
    Perturbation("start-noise", 0.0, 0.01),
)
"""The members' perturbations (names and units of :data:`PERTURBATIONS`), uniform draws."""

PHYSICS_STEPS_MS: tuple[int, ...] = (1, 2, 4)
"""The physics steps a member plays at, ms: those that divide the control step."""

CLEAN = "clean"
"""The name of a run's own verdict: no fall, no collision, no simulator warning, no error."""

VerdictStatus = Literal["holds", "fragile", "fails"]


def describe() -> str:
    """The ensemble in a few words, for ``--help``: ``friction 0.5..2, ..., physics step
    1/2/4 ms``."""
    ranges = ", ".join(f"{p.name} {p.low:g}..{p.high:g}" for p in ENSEMBLE)
    steps = "/".join(map(str, PHYSICS_STEPS_MS))
    return f"{ranges} (batch's perturbations), physics step {steps} ms"


def physics_steps(control_step_ms: int) -> tuple[int, ...]:
    """The steps of :data:`PHYSICS_STEPS_MS` that divide ``control_step_ms`` (ms): at most the
    control step, so a world's basicTimeStep bounds them."""
    return tuple(s for s in PHYSICS_STEPS_MS if control_step_ms % s == 0)


def member_specs(nominal: RunSpec, n: int, *, seed: int, control_step_ms: int) -> list[RunSpec]:
    """The ``n`` members of ``nominal``'s ensemble: samples 1..n, each with its draw of
    :data:`ENSEMBLE` (seeded by ``seed`` and its index, as ``batch --perturb`` draws) and a
    physics step (ms) of :func:`physics_steps` (``control_step_ms``), in its options: the
    steps in an order shuffled by ``seed``, taken in turn, so that 3 members play all three.

    Raises:
        MotionToolError: ``n`` < 1.
    """
    from motiontool.sim.batch import draw

    if n < 1:
        raise MotionToolError(f"an ensemble needs at least 1 member, got {n}")
    steps = list(physics_steps(control_step_ms))
    random.Random(f"{seed}:physics-step").shuffle(steps)  # every step played from n = 3 on
    options = {k: v for k, v in nominal.options if k not in ("rrd_dir", "rrd_name")}
    out = []
    for k in range(1, n + 1):
        step = steps[(k - 1) % len(steps)]
        member = {**options, "physics_step_ms": float(step)}
        out.append(
            replace(
                nominal,
                sample=k,
                params=draw(ENSEMBLE, seed, k),
                options=tuple(sorted(member.items())),
            )
        )
    return out


@dataclass(frozen=True)
class Disagreement:
    """A member whose verdict differs from the nominal run's.

    Attributes:
        sample: the member's index (1..n).
        values: its perturbation values (units in :data:`PERTURBATIONS`) and ``physics-step``
            (ms).
        passed: the member's verdict (True: passes where the nominal run does not).
        why: why it does not pass (empty when it passes).
    """

    sample: int
    values: dict[str, float]
    passed: bool
    why: str

    def to_json(self) -> dict[str, Any]:
        return {"sample": self.sample, "values": self.values, "passed": self.passed,
                "why": self.why}  # fmt: skip

    def summary(self) -> str:
        """``#3 (friction 0.61, mass 1.02, ...): fell at 1.20 s``."""
        values = ", ".join(f"{k} {v:.3g}" for k, v in self.values.items())
        return f"#{self.sample} ({values}): " + ("passes" if self.passed else self.why)


@dataclass(frozen=True)
class Verdict:
    """One verdict of a run over its ensemble.

    Attributes:
        name: ``clean`` or the expectation's text.
        status: ``holds``, ``fragile`` or ``fails`` (module docstring).
        members: the ensemble's size.
        disagree: the members whose verdict differs from the nominal run's.
    """

    name: str
    status: VerdictStatus
    members: int
    disagree: tuple[Disagreement, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "status": self.status,
            "members": self.members,
            "disagree": [d.to_json() for d in self.disagree],
        }

    def summary(self) -> str:
        """``fragile  dx >= 0.3: 2 of 4 members disagree``."""
        line = f"{self.status:<8} {self.name}"
        if self.disagree:
            line += f": {len(self.disagree)} of {self.members} members disagree"
        return line


@dataclass(frozen=True)
class Robustness:
    """A run's verdicts over its ensemble (:func:`judge`).

    Attributes:
        members: the ensemble's size; seed: the seed of its draws.
        verdicts: the clean verdict, then one per expectation, in order.
        draws: each member's values (sample 1..n, as :attr:`Disagreement.values`).
    """

    members: int
    seed: int
    verdicts: tuple[Verdict, ...]
    draws: tuple[dict[str, float], ...] = ()

    @property
    def fragile(self) -> bool:
        """Whether a verdict is fragile (a warning; ``--strict`` fails on it)."""
        return any(v.status == "fragile" for v in self.verdicts)

    def to_json(self) -> dict[str, Any]:
        return {
            "members": self.members,
            "seed": self.seed,
            "ensemble": {p.name: [p.low, p.high] for p in ENSEMBLE},
            "physics_steps_ms": list(PHYSICS_STEPS_MS),
            "fragile": self.fragile,
            "draws": [{"sample": k, "values": v} for k, v in enumerate(self.draws, 1)],
            "verdicts": [v.to_json() for v in self.verdicts],
        }

    def text(self) -> str:
        """:meth:`lines` as text, each line ending in a newline."""
        return "".join(f"{line}\n" for line in self.lines())

    def lines(self) -> list[str]:
        """The text report's lines: a title, then each verdict and its disagreeing members."""
        out = [f"robustness: {self.members} members (seed {self.seed})"]
        for v in self.verdicts:
            out.append(f"  {v.summary()}")
            out += [f"    {d.summary()}" for d in v.disagree]
        return out


def verdicts(report: PlayReport) -> list[tuple[str, bool, str]]:
    """``report``'s verdicts: (name, passed, why not) for ``clean`` (its problems other than
    its expectations), then each expectation."""
    failed = [r.reason for r in report.expectations if not r.passed]
    problems = report.problems
    own = problems[: len(problems) - len(failed)]  # expectations' reasons come last
    out = [(CLEAN, not own, "; ".join(own))]
    out += [(r.expectation.text, r.passed, r.reason) for r in report.expectations]
    return out


def _run_verdicts(result: RunResult) -> list[tuple[str, bool, str]] | None:
    """A batch run's verdicts, or None when it has no report (an error, a crash, a timeout)."""
    from motiontool.sim.expect import evaluate
    from motiontool.sim.report import PlayReport

    doc = result.full_report()
    if doc is None:
        return None
    report = PlayReport.from_json(doc)  # judged again: from_json keeps no expectations
    report.expectations = evaluate(result.spec.expect, report)
    return verdicts(report)


def _values(spec: RunSpec) -> dict[str, float]:
    values = dict(spec.params)
    values["physics-step"] = float(dict(spec.options)["physics_step_ms"])
    return values


def judge(
    nominal: PlayReport | RunResult, members: Sequence[RunResult], *, seed: int
) -> Robustness:
    """Each verdict of ``nominal`` (a judged report, or a batch run) over ``members`` (batch
    results of :func:`member_specs`, in order): holds, fragile or fails, with the members that
    disagree. A member that did not end with a report (an error, a crash, a timeout) disagrees
    with every verdict the nominal run passes; a nominal batch run without one fails ``clean``.
    """
    from motiontool.sim.batch_results import RunResult

    if isinstance(nominal, RunResult):
        theirs = _run_verdicts(nominal)
        ours = [(CLEAN, False, nominal.reason)] if theirs is None else theirs
    else:
        ours = verdicts(nominal)
    judged = [(m, _run_verdicts(m)) for m in members]
    out = []
    for i, (name, passed, _why) in enumerate(ours):
        disagree = []
        for result, member in judged:
            if member is None:
                their = (False, f"the run did not end: {result.status}: {result.reason}")
            else:
                their = member[i][1:]
            if their[0] != passed:
                disagree.append(Disagreement(result.spec.sample, _values(result.spec), *their))
        status: VerdictStatus = "fails" if not passed else "fragile" if disagree else "holds"
        out.append(Verdict(name, status, len(members), tuple(disagree)))
    draws = tuple(_values(m.spec) for m in members)
    return Robustness(len(members), seed, tuple(out), draws)


def with_members(
    specs: Sequence[RunSpec], n: int, *, seed: int, control_step_ms: Callable[[RunSpec], int | None]
) -> list[RunSpec]:
    """``specs`` (a batch's runs), then the ``n`` members of each (:func:`member_specs`) whose
    control step (ms; None: none, a run no robot fits) is known: what ``batch --robustness``
    runs, in one batch. :func:`regroup` takes the results apart again."""
    out = list(specs)
    for spec in specs:
        step = control_step_ms(spec)
        if step is not None:
            out += member_specs(spec, n, seed=seed, control_step_ms=step)
    return out


def regroup(batch: BatchResult, *, seed: int) -> BatchResult:
    """``batch`` (of :func:`with_members`: its runs, sample 0, then their members, 1..n) as its
    runs, each with its :class:`Robustness` (:func:`judge`) over its members (those of the same
    file, chain and robot); the members count in the wall time only."""
    members: dict[tuple[str, tuple[str, ...], str], list[RunResult]] = {}
    for result in batch.runs:
        if result.spec.sample:
            members.setdefault(_run_of(result.spec), []).append(result)
    out = []
    for result in (r for r in batch.runs if not r.spec.sample):
        mine = members.get(_run_of(result.spec), [])
        robust = judge(result, mine, seed=seed) if mine else None
        out.append(replace(result, robustness=robust))
    return replace(batch, runs=out)


def _run_of(spec: RunSpec) -> tuple[str, tuple[str, ...], str]:
    """The run a member belongs to: its motion, the chain played before it, its robot."""
    return spec.path, spec.chain, spec.robot
