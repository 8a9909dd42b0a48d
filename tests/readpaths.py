"""The reader's three paths side by side: exact (line by line, every check), fast (clean lines
without spans) and bulk (numpy loadtxt). Each must read every file exactly as the exact path does."""

from __future__ import annotations

import numpy as np

from motiontool.motionfmt import ReadResult, reader

PATHS = ("exact", "fast", "bulk")


def read_all(data: bytes, timestep_ms: int | None = 20) -> dict[str, ReadResult]:
    """The file read by each path."""
    return {
        "exact": reader._Reader(data, "f.motion", timestep_ms, exact=True).read(),
        "fast": reader._Reader(data, "f.motion", timestep_ms, bulk_min_bytes=1 << 62).read(),
        "bulk": reader._Reader(data, "f.motion", timestep_ms, bulk_min_bytes=0).read(),
    }


def _codes(result: ReadResult) -> list[str]:
    return [f"{d.code}@{d.line}:{d.column}" for d in result.diagnostics]


def differences(results: dict[str, ReadResult]) -> list[str]:
    """What each path reads differently from the exact path (empty when they agree): the
    verdict, the diagnostics, the poses, the values bit for bit (NaN positions included) and the
    commanded mask."""
    exact = results["exact"]
    want_rows = exact.values
    out = []
    for name in PATHS[1:]:
        got = results[name]
        if got.diagnostics != exact.diagnostics:
            out.append(f"{name}: diagnostics {_codes(got)} != {_codes(exact)}")
        for what in ("rejected_at", "joints", "times_ms", "pose_names"):
            if getattr(got, what) != getattr(exact, what):
                out.append(f"{name}: {what} {getattr(got, what)!r} != {getattr(exact, what)!r}")
        if list(got.pose_lines) != list(exact.pose_lines):
            out.append(f"{name}: pose_lines differ")
        rows = got.values
        if rows.shape != want_rows.shape:
            out.append(f"{name}: rows shape {rows.shape} != {want_rows.shape}")
            continue
        # Bit for bit, except that any NaN equals any NaN (its payload is not sent anywhere).
        same = (rows.view(np.int64) == want_rows.view(np.int64)) | (
            np.isnan(rows) & np.isnan(want_rows)
        )
        if not bool(same.all()):
            out.append(f"{name}: values differ at {np.argwhere(~same)[:3].tolist()}")
        if not np.array_equal(got.commanded, exact.commanded):
            out.append(f"{name}: commanded mask differs")
    return out
