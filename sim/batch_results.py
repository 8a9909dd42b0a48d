"""The results of a batch: how each run ended (:class:`RunResult`, with its report held, or
stored away by a batch that keeps its reports out of memory), and the batch's whole result in
plan order (:class:`BatchResult`)."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

if TYPE_CHECKING:
    from motiontool.sim.batch import RunSpec
    from motiontool.sim.robustness import Robustness

__all__ = ["CACHED_STATUSES", "BatchResult", "RunResult", "RunStatus", "result_json"]

RunStatus = Literal["clean", "failed", "error", "crashed", "timeout"]
"""How a run ended: ``clean`` (upright, no collision, no warning, every expectation met),
``failed`` (the run says why: fell, collided, simulator warning, an expectation not met),
``error`` (the runner raised), ``crashed`` (its worker died) or ``timeout``."""

CACHED_STATUSES: tuple[RunStatus, ...] = ("clean", "failed")
"""Runs that are cached: the simulation's own verdict (an error, crash or timeout is run again)."""


@dataclass
class RunResult:
    """The outcome of one run.

    Attributes:
        status: see :data:`RunStatus`.
        reason: one line for anything but ``clean``.
        report: the runner's full report (JSON-able), or None (none, or :attr:`stored`).
        wall_s: wall-clock seconds (0 for a cached result).
        cached: whether it came from the cache.
        stored: where a batch that keeps its reports out of memory stored this one (JSON);
            :meth:`full_report` reads it back.
        tilt_deg: the base's largest tilt, deg (from the report, kept when it is stored):
            what ranks a run among its motion's runs.
        robustness: its verdicts over its ``--robustness`` members
            (:mod:`motiontool.sim.robustness`); None: not asked for.
    """

    spec: RunSpec
    status: RunStatus
    reason: str = ""
    report: dict[str, Any] | None = None
    wall_s: float = 0.0
    cached: bool = False
    stored: Path | None = None
    tilt_deg: float | None = None
    robustness: Robustness | None = None

    def __post_init__(self) -> None:
        if self.report is not None and self.tilt_deg is None:
            value = (self.report.get("base") or {}).get("max_tilt_deg")
            self.tilt_deg = float(value) if isinstance(value, int | float) else None

    @property
    def ok(self) -> bool:
        return self.status == "clean"

    def full_report(self) -> dict[str, Any] | None:
        """The runner's report: held, or read back from where the batch stored it."""
        if self.stored is None:
            return self.report
        loaded: dict[str, Any] = json.loads(self.stored.read_bytes())
        return loaded


@dataclass
class BatchResult:
    """Every run of a batch, in plan order, with totals."""

    runs: list[RunResult] = field(default_factory=list)
    wall_s: float = 0.0
    executor: str = "local"
    jobs: int = 1
    models: dict[str, str] = field(default_factory=dict)
    """The sha256 of each robot model the batch ran on, by robot (as the runs name it)."""

    @property
    def model_sha256(self) -> str | None:
        """The model every run ran on, or None: several models (see :attr:`models`), or none."""
        hashes = set(self.models.values())
        return hashes.pop() if len(hashes) == 1 else None

    @property
    def failures(self) -> list[RunResult]:
        return [r for r in self.runs if not r.ok]


def result_json(result: RunResult) -> dict[str, Any]:
    """A run as JSON: its spec, status, reason, wall time (s), cache flag and full report."""
    return {
        "spec": asdict(result.spec),
        "status": result.status,
        "reason": result.reason,
        "wall_s": round(result.wall_s, 3),
        "cached": result.cached,
        "report": result.full_report(),
        **({} if result.robustness is None else {"robustness": result.robustness.to_json()}),
    }
