"""MT307: self-collision of the robot's bodies at every keyframe and segment midpoint."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

from motiontool.errors import MissingExtraError
from motiontool.extras import require_installed
from motiontool.kinematics.checks._table import (
    GroupingCheck,
    Table,
    cell,
    configurations,
    fmt_ms,
)
from motiontool.kinematics.checks.registry import DEFAULT_PENETRATION_TOLERANCE_MM, CheckOptions
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.diagnostics import SELF_COLLISION, Diagnostic, Severity
from motiontool.motionfmt.findings import Findings, in_order
from motiontool.motionfmt.grouping import MAX_RUNS
from motiontool.motionfmt.reader import ReadResult
from motiontool.motionfmt.units import MM_PER_M

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.kinematics.distinct_rows import Known

__all__ = ["DEFAULT_PENETRATION_TOLERANCE_MM", "Collision"]

_POSES = 8192
"""Keyframes whose configurations (and the segment midpoints after them) are scanned at a time:
the arrays of a block, not of the whole file, are held (:func:`scan_self_collisions`)."""

_KEPT_ROWS = 1 << 16
"""The most configurations (keyframes and midpoints) of a file whose contacts the check keeps
for the next version of the file (about 14 MB for the Nao)."""


class Collision(GroupingCheck):
    """MT307: self-collision at every keyframe and segment midpoint (one diagnostic per pair
    of bodies and run of consecutive checked instants; grouped, one per pair where it has more
    than :data:`~motiontool.motionfmt.grouping.MAX_RUNS` runs)."""

    def __init__(
        self, spec: RobotSpec, penetration_tolerance_mm: float = DEFAULT_PENETRATION_TOLERANCE_MM
    ) -> None:
        super().__init__(spec)
        self.tolerance_mm = penetration_tolerance_mm
        self._known: Known | None = None
        """The contacts at each configuration met (the first ones), by every motion this check
        scans: a cycle met again is not scanned again."""
        self._last: _Scan | None = None
        """The configurations of the last file scanned and their contacts (where it has at most
        :data:`_KEPT_ROWS`): an edit of it (``motiontool server`` keeps its checks from one
        version to the next) scans the configurations it changed, not the others."""
        self._pairs: list[tuple[str, str]] = []  # the pairs of bodies met, by index
        self._pair_index: dict[tuple[str, str], int] = {}

    @classmethod
    def for_run(cls, spec: RobotSpec, options: CheckOptions) -> Collision:
        """The check of ``spec`` with the run's tolerance."""
        return cls(spec, options.penetration_tolerance_mm)

    def _check(self, result: ReadResult, *, group: bool) -> Findings:
        import numpy as np

        from motiontool.kinematics.collision import body_joints

        table = self.table(result)
        if not table.motors:
            return Findings.of([])
        times = np.empty(2 * table.times.shape[0] - 1)
        scan = self._scan(table, times)
        found = _overlap_runs(scan, self._pairs, group)
        joints = body_joints(self.spec, fingers_in_hand=True) if found.pair.size else {}
        return in_order(
            (found.deepest + 1) // 2,
            np.full(found.pair.shape, -1),
            lambda i: self._overlap(table, times, joints, found, i),
        )

    def _scan(self, table: Table, times: npt.NDArray[np.float64]) -> _Scan:
        """The contacts at every configuration of ``table`` (:func:`configurations`: keyframes
        and segment midpoints; their times, ms, written to ``times``), a block of
        :data:`_POSES` keyframes at a time. A configuration the last file scanned had at the
        same row, or at the same row counted from the end (an edit of the file the server
        checked last), takes its contacts from there; the others are scanned."""
        import numpy as np

        from motiontool.kinematics.collision import Known, scan_self_collisions

        # Pinocchio is imported only for the pairs numpy cannot clear (kinematics.collision).
        what = "the collision check"
        require_installed("pinocchio", "kinematics", what)
        if self._known is None:
            self._known = Known()
        n_rows, last = times.shape[0], self._last
        kept: list[npt.NDArray[np.float64]] | None = [] if n_rows <= _KEPT_ROWS else None
        found: list[_Scan] = []
        for lo in range(0, table.times.shape[0], _POSES):  # configuration 2 * lo is the first
            q, times[2 * lo : 2 * lo + 2 * _POSES] = configurations(
                table, self.spec, lo, lo + _POSES
            )
            rows = 2 * lo + np.arange(q.shape[0])
            source = np.full(q.shape[0], -1) if last is None else last.rows_of(q, rows, n_rows)
            fresh = np.flatnonzero(source < 0)
            try:
                contacts = scan_self_collisions(
                    self.spec,
                    q[fresh],
                    penetration_tolerance_m=self.tolerance_mm / MM_PER_M,
                    fingers_in_hand=True,
                    known=self._known,
                )
            except MissingExtraError as exc:  # installed, but it (or coal) fails to import
                raise MissingExtraError(exc.module, exc.extra, what, exc.library) from exc
            pair = np.array([self._pair((c.body_a, c.body_b)) for c in contacts], dtype=np.intp)
            found.append(
                _Scan(
                    None,
                    rows[fresh[[c.config for c in contacts]]].astype(np.intp),
                    pair,
                    np.array([c.depth_m for c in contacts], dtype=np.float64),
                )
            )
            if last is not None and fresh.size < q.shape[0]:
                found.append(last.moved(rows, source))
            if kept is not None:
                kept.append(q)
        scan = _Scan.joined(found, None if kept is None else np.concatenate(kept))
        self._last = scan if kept is not None else None
        return scan

    def _pair(self, pair: tuple[str, str]) -> int:
        """The index of a pair of bodies in :attr:`_pairs` (added if new)."""
        at = self._pair_index.get(pair)
        if at is None:
            at = self._pair_index[pair] = len(self._pairs)
            self._pairs.append(pair)
        return at

    def _overlap(
        self,
        table: Table,
        times: npt.NDArray[np.float64],
        joints: dict[str, str | None],
        runs: _Runs,
        i: int,
    ) -> Diagnostic:
        """MT307 for run ``i`` of ``runs``: two bodies overlapping over consecutive checked
        instants (indices in ``times``, ms), or over several runs of them where grouped; each
        body named with the motor that carries it (``joints``), the joint a user edits."""
        deepest, n_runs, size = int(runs.deepest[i]), int(runs.runs[i]), int(runs.size[i])
        depth_mm = float(runs.depth[i]) * MM_PER_M
        at = self._instant(table, times, deepest)
        start, end = fmt_ms(times[runs.first[i]]), fmt_ms(times[runs.last[i]])
        span = "" if size == 1 else f"; they overlap from {start} to {end}"
        if n_runs > 1:
            span = f"; they overlap at {size:,} instants in {n_runs:,} runs, from {start} to {end}"
        a, b = (_body(joints.get(body), body) for body in self._pairs[int(runs.pair[i])])
        return cell(
            table,
            SELF_COLLISION,
            Severity.WARNING,
            (deepest + 1) // 2,
            None,
            f"{a} and {b} overlap by {depth_mm:.1f} mm at {at}{span}",
            f"overlaps under {self.tolerance_mm:g} mm are ignored as artefacts of the "
            "coarse collision shapes; a simulator with self-collision off lets the "
            f"bodies pass through each other, the real {self.spec.name} does not",
            time_ms=math.floor(times[deepest]),
        )

    @staticmethod
    def _instant(table: Table, times: npt.NDArray[np.float64], index: int) -> str:
        if index % 2 == 0:
            return f"{fmt_ms(times[index])} (pose '{table.result.pose_names[index // 2]}')"
        p = index // 2
        return (
            f"{fmt_ms(times[index])}, halfway from {int(table.times[p])} ms to "
            f"{int(table.times[p + 1])} ms"
        )


class _Scan(NamedTuple):
    """The contacts found at the configurations of one file: (C,) each, sorted by row."""

    q: npt.NDArray[np.float64] | None
    """(R, M) the configurations (where kept), rad or m."""
    row: npt.NDArray[np.intp]
    """The configuration of each contact."""
    pair: npt.NDArray[np.intp]
    """Its two bodies, an index in :attr:`Collision._pairs`."""
    depth: npt.NDArray[np.float64]
    """How deep they overlap, m."""

    @classmethod
    def joined(cls, parts: list[_Scan], q: npt.NDArray[np.float64] | None) -> _Scan:
        """The contacts of ``parts`` sorted by row, at configurations ``q``."""
        import numpy as np

        row = np.concatenate([p.row for p in parts])
        order = np.argsort(row, kind="stable")
        pair = np.concatenate([p.pair for p in parts])[order]
        return cls(q, row[order], pair, np.concatenate([p.depth for p in parts])[order])

    def rows_of(
        self, q: npt.NDArray[np.float64], rows: npt.NDArray[np.intp], n_rows: int
    ) -> npt.NDArray[np.intp]:
        """For each configuration ``q[i]`` (row ``rows[i]`` of a file of ``n_rows``; the rows
        consecutive), the row of these configurations with the same bytes, at the same row or
        else at the same row from the end; -1 where neither is."""
        import numpy as np

        source = np.full(q.shape[0], -1)
        if self.q is None or self.q.shape[1] != q.shape[1]:
            return source
        bits, kept = q.view(np.uint64), self.q.view(np.uint64)
        first = int(rows[0])  # the rows are consecutive
        for shift in (0, n_rows - kept.shape[0]):  # the same row, the same row from the end
            lo, hi = max(first - shift, 0), min(first - shift + q.shape[0], kept.shape[0])
            if lo >= hi:
                continue
            i = np.arange(lo, hi)  # rows of the kept configurations, i + shift - first of q
            same = (bits[lo + shift - first : hi + shift - first] == kept[lo:hi]).all(axis=1)
            found = source[i[same] + shift - first] < 0
            source[i[same][found] + shift - first] = i[same][found]
        return source

    def moved(self, rows: npt.NDArray[np.intp], source: npt.NDArray[np.intp]) -> _Scan:
        """The contacts of rows ``source[i]`` (those >= 0) as contacts of rows ``rows[i]``."""
        import numpy as np

        assert self.q is not None, "the contacts of configurations not kept"
        starts = np.searchsorted(self.row, np.arange(self.q.shape[0] + 1))
        take = np.flatnonzero(source >= 0)
        first, count = starts[source[take]], starts[source[take] + 1] - starts[source[take]]
        offsets = np.cumsum(count) - count
        at = np.repeat(first - offsets, count) + np.arange(int(count.sum()))
        return _Scan(None, np.repeat(rows[take], count), self.pair[at], self.depth[at])


class _Runs(NamedTuple):
    """The findings of MT307, (F,) each: a pair of bodies and a run of consecutive checked
    instants where they overlap (several runs where grouped)."""

    pair: npt.NDArray[np.intp]
    first: npt.NDArray[np.intp]
    last: npt.NDArray[np.intp]
    deepest: npt.NDArray[np.intp]
    depth: npt.NDArray[np.float64]
    size: npt.NDArray[np.intp]
    """How many instants."""
    runs: npt.NDArray[np.intp]
    """How many runs (1 but where grouped)."""


def _overlap_runs(scan: _Scan, pairs: list[tuple[str, str]], group: bool) -> _Runs:
    """The runs of consecutive instants of each pair of bodies of ``scan`` (the pairs in the
    order of their names, each one's runs in time order), each with its deepest instant (the
    first of the deepest); with ``group``, a pair's runs as one where it has more than
    :data:`~motiontool.motionfmt.grouping.MAX_RUNS`."""
    import numpy as np

    rank = np.empty(len(pairs), dtype=np.intp)
    rank[sorted(range(len(pairs)), key=pairs.__getitem__)] = np.arange(len(pairs))
    order = np.lexsort((scan.row, rank[scan.pair])) if pairs else np.zeros(0, dtype=np.intp)
    row, pair, depth = scan.row[order], scan.pair[order], scan.depth[order]
    new_pair = np.ones(row.shape, dtype=bool)
    new_pair[1:] = pair[1:] != pair[:-1]
    new_run = new_pair.copy()
    new_run[1:] |= row[1:] != row[:-1] + 1
    run_of = np.cumsum(new_run) - 1
    if group:  # a pair's runs as one where it has too many
        pair_of = np.cumsum(new_pair) - 1
        runs_per_pair = np.bincount(pair_of[new_run], minlength=int(new_pair.sum()))
        merged = runs_per_pair[pair_of] > MAX_RUNS
        new_run &= ~merged | new_pair
        n_runs = np.where(merged, runs_per_pair[pair_of], 1)
    else:
        n_runs = np.ones(row.shape, dtype=np.intp)
    starts = np.flatnonzero(new_run)
    ends = np.append(starts[1:], row.shape[0]) - 1
    if starts.size == 0:
        empty = np.zeros(0, dtype=np.intp)
        return _Runs(empty, empty, empty, empty, np.zeros(0), empty, empty)
    run_of = np.cumsum(new_run) - 1
    deepest_depth = np.maximum.reduceat(depth, starts)
    is_max = depth == deepest_depth[run_of]
    at_max = np.flatnonzero(is_max)
    _runs, first_max = np.unique(run_of[at_max], return_index=True)
    deepest = at_max[first_max]
    return _Runs(
        pair[starts],
        row[starts],
        row[ends],
        row[deepest],
        depth[deepest],
        ends - starts + 1,
        n_runs[starts],
    )


def _body(joint: str | None, body: str) -> str:
    """A body as MT307 names it: ``RWristYaw body 'r_hand'``, ``root body 'torso'``."""
    return f"{joint or 'root'} body '{body}'"
