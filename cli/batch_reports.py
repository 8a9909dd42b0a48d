"""Reports of a batch: a summary table, JUnit XML, JSON and Markdown (for a PR comment)."""

from __future__ import annotations

import re
import tempfile
from collections import defaultdict
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from motiontool.cli.jsontext import (
    HOLE,
    dumps_around,
    escape_undecodable,
    indented,
    list_pieces,
    text_after,
)
from motiontool.extras import require
from motiontool.motionfmt.fileio import atomic_write
from motiontool.sim.batch_results import BatchResult, RunResult, result_json
from motiontool.stamps import stamps

__all__ = [
    "md_cell",
    "motion_rows",
    "render_json",
    "render_markdown",
    "render_summary",
    "robustness_lines",
    "write_junit",
]


def motion_rows(batch: BatchResult) -> list[dict[str, Any]]:
    """Per (motion, robot): runs, share clean, and the worst run (largest tilt, or a failure)."""
    groups: dict[tuple[str, str], list[RunResult]] = defaultdict(list)
    for r in batch.runs:
        groups[(r.spec.shown, r.spec.robot)].append(r)
    rows = []
    for (path, robot), runs in groups.items():
        clean = sum(r.ok for r in runs)

        def badness(r: RunResult) -> tuple[int, float]:
            return (0 if r.ok else 1, r.tilt_deg or 0.0)

        worst = max(runs, key=badness)
        rows.append(
            {
                "motion": path,
                "robot": robot,
                "runs": len(runs),
                "clean": clean,
                "clean_share": clean / len(runs),
                "worst": worst.spec.label,
                "worst_status": worst.status,
                "worst_reason": worst.reason,
                "worst_max_tilt_deg": worst.tilt_deg,
            }
        )
    return rows


def render_summary(batch: BatchResult) -> str:
    """A plain-text table for the terminal, then one line of totals."""
    rows = motion_rows(batch)
    header = ("motion", "robot", "runs", "clean", "worst case")
    table = [header] + [
        (
            row["motion"],
            row["robot"],
            str(row["runs"]),
            f"{row['clean']} ({100 * row['clean_share']:.0f} %)",
            "-"
            if row["worst_status"] == "clean"
            else f"{row['worst_status']}: {row['worst_reason']}",
        )
        for row in rows
    ]
    widths = [max(len(r[i]) for r in table) for i in range(len(header))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)).rstrip() for r in table]
    runs = len(batch.runs)
    cached = sum(r.cached for r in batch.runs)
    simulated = runs - cached
    # A rate of the runs simulated: a batch the cache answered whole simulated none.
    pace = (
        f"{simulated / batch.wall_s:.2f} runs/s"
        if simulated and batch.wall_s > 0
        else "none simulated"
    )
    lines.append(
        f"{runs} runs: {runs - len(batch.failures)} clean, {len(batch.failures)} not clean,"
        f" {cached} from cache; {batch.wall_s:.1f} s wall, {pace}"
        f" ({batch.executor}, {batch.jobs} jobs)"
    )
    return "\n".join(lines + robustness_lines(batch)) + "\n"


def robustness_lines(batch: BatchResult) -> list[str]:
    """Each run's verdicts over its ``--robustness`` members, and the members that disagree
    (none without --robustness)."""
    lines = []
    for r in batch.runs:
        if r.robustness is not None:
            lines.append(f"{r.spec.label}: {r.robustness.lines()[0]}")
            lines += r.robustness.lines()[1:]
    members = sum(r.robustness.members for r in batch.runs if r.robustness is not None)
    if members:  # the runs/s above counts the runs alone
        lines.insert(
            0, f"--robustness: {members} members played besides the runs, in the wall time"
        )
    return lines


def render_json(batch: BatchResult) -> Iterator[str]:
    """Every run's full report, with the batch's stamps and totals (units in the keys), in
    pieces: one run's report at a time, read back where the batch stored it; the same text as
    :func:`~motiontool.cli.jsontext.dumps` of the whole document."""
    doc: dict[str, Any] = {
        "schema": "motiontool.batch",
        "schema_version": 1,
        "stamps": stamps(batch.model_sha256),
        "models": batch.models,
        "executor": batch.executor,
        "jobs": batch.jobs,
        "wall_s": round(batch.wall_s, 3),
        "summary": {
            "runs": len(batch.runs),
            "clean": len(batch.runs) - len(batch.failures),
            "not_clean": len(batch.failures),
            "cached": sum(r.cached for r in batch.runs),
        },
        "motions": motion_rows(batch),
        "runs": HOLE,
    }
    yield dumps_around(doc, 0)[0]
    counter = [0]
    yield from list_pieces(_runs(batch, counter), 1)
    yield text_after(doc, counter[0])


def _runs(batch: BatchResult, escaped: list[int]) -> Iterator[str]:
    """Each run as JSON text, its report read as it is written; ``escaped[0]`` adds up the
    undecodable bytes escaped."""
    for r in batch.runs:
        clean, n = escape_undecodable(result_json(r))
        escaped[0] += n
        yield indented(clean)


def md_cell(text: object) -> str:
    """``text`` as one Markdown table cell: ``|`` escaped, line breaks as spaces, HTML's ``<``
    and ``&`` escaped (a reason or a file name cannot split the row or open a tag)."""
    flat = " ".join(str(text).splitlines())
    return flat.replace("&", "&amp;").replace("<", "&lt;").replace("|", "\\|")


def _md_code(text: str) -> str:
    """``text`` as inline code in a table cell (backticks in it lengthen the fence)."""
    flat = " ".join(text.splitlines()).replace("|", "\\|")
    ticks = max((len(run) for run in re.findall(r"`+", flat)), default=0)
    fence = "`" * (ticks + 1)
    pad = " " if flat.startswith("`") or flat.endswith("`") else ""
    return f"{fence}{pad}{flat}{pad}{fence}"


def render_markdown(batch: BatchResult) -> str:
    """A Markdown table for a pull-request comment (every cell escaped: :func:`md_cell`)."""
    lines = [
        "### motiontool batch",
        "",
        "| motion | robot | runs | clean | worst case |",
        "|---|---|---:|---:|---|",
    ]
    for row in motion_rows(batch):
        worst = (
            "—"
            if row["worst_status"] == "clean"
            else f"{row['worst_status']}: {row['worst_reason']}"
        )
        lines.append(
            f"| {_md_code(row['motion'])} | {md_cell(row['robot'])} | {row['runs']} |"
            f" {row['clean']} ({100 * row['clean_share']:.0f} %) | {md_cell(worst)} |"
        )
    lines += [
        "",
        f"{len(batch.runs)} runs, {len(batch.failures)} not clean, {batch.wall_s:.1f} s wall"
        f" ({batch.executor}, {batch.jobs} jobs); motiontool {stamps()['motiontool']},"
        f" MuJoCo {stamps()['mujoco']}.",
    ]
    return "\n".join(lines + _md_robustness(batch)) + "\n"


def _md_robustness(batch: BatchResult) -> list[str]:
    """A table of every ``--robustness`` verdict: the run, the verdict, holds / fragile /
    fails, and the members that disagree with their values (none without --robustness)."""
    rows = [
        f"| {_md_code(r.spec.label)} | {_md_code(v.name)} | {v.status} |"
        f" {md_cell('; '.join(d.summary() for d in v.disagree) or '—')} |"
        for r in batch.runs
        if r.robustness is not None
        for v in r.robustness.verdicts
    ]
    if not rows:
        return []
    head = ["", "#### Robustness", "", "| run | verdict | status | members that disagree |"]
    return [*head, "|---|---|---|---|", *rows]


def write_junit(batch: BatchResult, path: Path) -> None:
    """JUnit XML: one test case per run; failures and errors carry the reason."""
    require("junitparser", "sim", "motiontool batch --junit")
    from junitparser import Error, Failure, JUnitXml, TestCase, TestSuite

    suite = TestSuite("motiontool batch")
    for r in batch.runs:
        case = TestCase(
            r.spec.label, classname=f"motiontool.{r.spec.robot}", time=round(r.wall_s, 3)
        )
        if r.status == "failed":
            case.result = [Failure(r.reason, "not clean")]
        elif not r.ok:
            case.result = [Error(r.reason, r.status)]
        if r.robustness is not None:  # each verdict, the members that disagree
            case.system_out = "\n".join(r.robustness.lines())
        suite.add_testcase(case)
    suite.update_statistics()  # type: ignore[no-untyped-call]
    xml = JUnitXml()
    xml.add_testsuite(suite)
    with tempfile.TemporaryDirectory() as tmp:
        scratch = Path(tmp) / "junit.xml"
        xml.write(str(scratch), pretty=True)
        atomic_write(path, scratch.read_bytes())
