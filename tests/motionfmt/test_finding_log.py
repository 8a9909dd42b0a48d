"""FindingLog (motionfmt/finding_log.py): the reader's findings, the oldest on disk, read as the
list they replace, sorted as a stable sort of that list sorts them; a file with thousands of
findings keeps them in bounded memory."""

from __future__ import annotations

import pickle
import tracemalloc
from unittest import mock

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from motiontool.motionfmt import finding_log, read_bytes
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.finding_log import FindingLog
from motiontool.motionfmt.findings import Findings


def finding(i: int, line: int, column: int = 1, code: str = "MT203") -> Diagnostic:
    return Diagnostic(
        code=code,
        severity=Severity.WARNING,
        path="f.motion",
        line=line,
        column=column,
        message=f"finding {i}",
    )


# Lines mostly rising (the reader's order), now and then one back (a check of the whole motion),
# and places met twice (a stable sort keeps their order).
LINES = st.lists(st.integers(1, 30), max_size=120).map(
    lambda xs: [x if k % 7 else x // 3 for k, x in enumerate(sorted(xs))] + xs[:5]
)


@settings(max_examples=200, deadline=None)
@given(lines=LINES, chunk=st.sampled_from([1, 2, 3, 8]), cut=st.integers(0, 130))
def test_the_log_reads_as_the_list_and_sorts_as_a_stable_sort(
    lines: list[int], chunk: int, cut: int
) -> None:
    with (
        mock.patch.object(finding_log, "CHUNK", chunk),
        mock.patch.object(finding_log, "HELD", 2 * chunk),
    ):
        want = [finding(i, line) for i, line in enumerate(lines)]
        log = FindingLog(want)
        assert len(log) == len(want)
        assert log == want and list(log) == want
        assert [log[i] for i in range(len(want))] == want
        assert log[cut:] == want[cut:] and log[:cut] == want[:cut] and log[-3:] == want[-3:]
        assert list(Findings.of(log)) == sorted(want, key=Diagnostic.sort_key)
        assert pickle.loads(pickle.dumps(log)) == want
        # Taking back the last ones (a cut line keeps only where Webots stops), then going on.
        del log[cut:]
        del want[cut:]
        assert log == want
        more = [finding(1000 + i, line) for i, line in enumerate(lines[:9])]
        for d in more:
            log.append(d)
        want += more
        assert log == want
        assert list(log.in_order()) == sorted(want, key=Diagnostic.sort_key)


def test_only_the_last_findings_can_be_taken_back() -> None:
    log = FindingLog([finding(i, i + 1) for i in range(5)])
    with pytest.raises(TypeError, match="last findings"):
        del log[1:3]


def test_a_file_with_a_finding_a_cell_holds_a_few_chunks_of_them() -> None:
    """26 findings a line (a unit on every cell) on 4,000 lines: 104,000 findings, 52 MB as
    objects; what the read holds of them stays under 8 MB (4,096 held, here), and every one
    reads back in order."""
    cells = ",".join(["0.5rad"] * 26)
    joints = ",".join(f"J{j}" for j in range(26))
    lines = "".join(f"{40 * p},P{p},{cells}\n" for p in range(4000))
    data = f"#WEBOTS_MOTION,V1.0,{joints}\n{lines}".encode()
    tracemalloc.start()
    try:
        with (
            mock.patch.object(finding_log, "CHUNK", 1024),
            mock.patch.object(finding_log, "HELD", 4096),
        ):
            result = read_bytes(data, "units.motion", timestep_ms=None)
        held, _peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert len(result.diagnostics) == 104_000
    assert held < 8 * 2**20 + 5 * len(data)  # the file's own arrays besides
    order = [(d.line, d.column) for d in Findings.of(result.diagnostics)]
    assert order == sorted(order) and order[0] == (2, len("0,P0,0.5") + 1)  # at 'rad'
    assert len(set(order)) == len(order)


def test_what_is_taken_back_leaves_no_trace_in_the_order() -> None:
    """A run started by findings taken back (a cut line's) ends with them: a finding appended
    next is placed after the ones kept."""
    log = FindingLog([finding(0, 5), finding(1, 9), finding(2, 2)])
    del log[2:]
    log.append(finding(3, 7))
    assert [d.line for d in log.in_order()] == [5, 7, 9]


def test_where_no_temporary_file_can_be_written_the_findings_are_held() -> None:
    def refuse(*_args: object, **_kwargs: object) -> None:
        raise OSError(28, "No space left on device")

    with (
        mock.patch.object(finding_log, "CHUNK", 2),
        mock.patch.object(finding_log, "HELD", 4),
        mock.patch("tempfile.TemporaryFile", refuse),
    ):
        want = [finding(i, i + 1) for i in range(50)]
        log = FindingLog(want)
        assert log == want and list(log.in_order()) == want
