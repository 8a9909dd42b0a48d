"""The generator's entry points: :func:`generate` (every output's text) and :func:`main` (the
command line, which writes the files or checks that they are up to date)."""

from __future__ import annotations

import argparse
import json
from collections.abc import Sequence
from pathlib import Path

from motiontool.kinematics._modelgen.nao import nao_xml
from motiontool.kinematics._modelgen.nao_v5 import nao_v5_json
from motiontool.kinematics._modelgen.ur5e import ur5e_xml

__all__ = ["generate", "main"]

_SOURCES = ("nao.json", "ur5e.json")
_OUTPUTS = ("nao.xml", "nao-v5.json", "ur5e.xml")
#: The first line of the package's docstring.
_DESCRIPTION = (
    "Generate the built-in robot models from the robot data JSON (the single source of truth)."
)


def generate(source_dir: Path) -> dict[str, str]:
    """Build every output file's text from the JSON in ``source_dir``; keys are file names."""
    nao_src, ur_src = (source_dir / name for name in _SOURCES)
    nao = json.loads(nao_src.read_text(encoding="utf-8"))
    ur5e = json.loads(ur_src.read_text(encoding="utf-8"))
    return {
        "nao.xml": nao_xml(nao, nao_src),
        "nao-v5.json": nao_v5_json(nao, nao_src),
        "ur5e.xml": ur5e_xml(ur5e, ur_src),
    }


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m motiontool.kinematics._modelgen", description=_DESCRIPTION
    )
    parser.add_argument(
        "source_dir",
        type=Path,
        metavar="robots-dir",
        help="folder holding nao.json and ur5e.json (e.g. tests/data/robot_facts)",
    )
    parser.add_argument("output_dir", type=Path, help="folder to write the models into")
    parser.add_argument(
        "--check", action="store_true", help="write nothing; exit 1 if a file is out of date"
    )
    args = parser.parse_args(argv)
    for name in _SOURCES:
        if not (args.source_dir / name).is_file():
            parser.error(
                f"{args.source_dir / name}: not found (robots-dir holds {' and '.join(_SOURCES)})"
            )
    outputs = generate(args.source_dir)
    stale = []
    for name in _OUTPUTS:
        target = args.output_dir / name
        data = outputs[name].encode("utf-8")
        if target.exists() and target.read_bytes() == data:
            continue
        stale.append(name)
        if not args.check:
            args.output_dir.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
    verb = "out of date" if args.check else "written"
    for name in stale:
        print(f"{args.output_dir / name}: {verb}")
    return 1 if (args.check and stale) else 0
