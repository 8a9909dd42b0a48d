"""Regenerate the golden expectations: ``python tests/data/regen.py``, then review the diff.

For every ``valid/*.motion`` and ``invalid/*.motion``: ``NAME.expected`` holds the diagnostics
exactly as ``validate`` words them (compiler line, then the hint); for files Webots accepts,
``NAME.json`` holds what Webots reads (joints, pose names, times in ms, values as ``repr`` or
null for no command).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from motiontool.motionfmt.reader import read_bytes

HERE = Path(__file__).parent
TIMESTEP = {"timestep_offgrid": 20, "clock_wraps": 1_000_000_000}


def expected_text(path: Path) -> str:
    result = read_bytes(path.read_bytes(), path.name, timestep_ms=TIMESTEP.get(path.stem))
    lines = []
    for d in result.diagnostics:
        lines.append(d.format())
        if d.hint:
            lines.append(f"  hint: {d.hint}")
    return "\n".join(lines) + ("\n" if lines else "")


def expected_parse(path: Path) -> dict[str, object]:
    result = read_bytes(path.read_bytes(), path.name)
    return {
        "joints": result.joints,
        "pose_names": list(result.pose_names),
        "times_ms": list(result.times_ms),
        "values": [
            [None if math.isnan(v) else repr(v) for v in result.row(p)]
            for p in range(len(result.times_ms))
        ],
    }


def main() -> None:
    for kind in ("valid", "invalid"):
        for path in sorted((HERE / kind).glob("*.motion")):
            path.with_suffix(".expected").write_text(expected_text(path), encoding="utf-8")
            if kind == "valid":
                parse = json.dumps(expected_parse(path), indent=1, ensure_ascii=True)
                path.with_suffix(".json").write_text(parse + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
