"""``sample``'s output text, chunk by chunk: the CSV rows and the JSON document, each written as
its chunk of the stream is computed, and byte for byte what ``csv.writer`` and ``json.dumps``
write for the whole stream.

A chunk's rows are spelt by ``str`` of their Python lists (C code: the shortest round-trip
``repr`` of every float, as ``csv`` and ``json`` spell them); the cells that are not plain
numbers are then rewritten whole: no command (marked with Webots' -9999999.9, which a sent
target never equals) and, in JSON, the strings ``"nan"``, ``"inf"``, ``"-inf"``.
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING

from motiontool.cli.jsontext import ESCAPED_BYTES, escape_undecodable
from motiontool.motionfmt.reader import NO_VALUE_MARKER
from motiontool.stamps import stamps

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.player import CommandStream

__all__ = ["csv_header", "csv_rows", "json_document"]

_UNSENT = repr(NO_VALUE_MARKER)
_CSV_CELLS = {_UNSENT: ""}
_JSON_CELLS = {_UNSENT: "null"}
_JSON_NON_FINITE = {"nan": '"nan"', "inf": '"inf"', "-inf": '"-inf"'}


def _rewrite_cells(text: str, cells: Mapping[str, str]) -> str:
    """``text`` (``str`` of a list of lists) with every cell that reads exactly like a key of
    ``cells`` replaced by its value. A cell starts after ``[`` or ``, `` and ends before ``,``
    or ``]``; matches never overlap, as each ends with the ``,`` before the next cell's space."""
    for old, new in cells.items():
        for before in ("[", " "):
            for after in (",", "]"):
                text = text.replace(before + old + after, before + new + after)
    return text


def _values(chunk: CommandStream) -> npt.NDArray[np.float64]:
    """The chunk's targets (S, J), Webots' -9999999.9 where no command is sent."""
    import numpy as np

    return np.where(chunk.commanded, chunk.targets, NO_VALUE_MARKER)


def csv_header(joints: Sequence[str]) -> str:
    """``time_ms,<joint>,...`` as ``csv.writer`` quotes it (any joint name survives)."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow(["time_ms", *joints])
    return buffer.getvalue()


def csv_rows(chunk: CommandStream) -> str:
    """The chunk's rows, ``time_ms,value,...`` each: shortest round-trip ``repr`` (``nan``,
    ``inf``, ``-inf`` included), an empty cell where no command is sent."""
    rows = [
        [t, *values]
        for t, values in zip(chunk.elapsed_ms.tolist(), _values(chunk).tolist(), strict=True)
    ]
    text = _rewrite_cells(str(rows), _CSV_CELLS)  # numbers never need csv quoting
    return text[2:-2].replace("], [", "\n").replace(", ", ",") + "\n"


def _json_targets(chunk: CommandStream) -> str:
    """The chunk's rows as the items of a JSON array (no brackets around them)."""
    import numpy as np

    values = _values(chunk)
    text = _rewrite_cells(str(values.tolist()), _JSON_CELLS)
    if not bool(np.isfinite(values).all()):
        text = _rewrite_cells(text, _JSON_NON_FINITE)
    return text[1:-1]


def json_document(
    path: str,
    timestep_ms: int,
    joints: Sequence[str],
    elapsed: Iterable[npt.NDArray[np.int64]],
    stream: Iterable[CommandStream],
) -> Iterator[str]:
    """The ``motiontool.sample`` JSON document (``cli/schemas/sample.schema.json``) in pieces:
    the head, then ``elapsed_ms`` chunk by chunk, then ``targets`` (a second pass over the
    stream, whose chunks must hold the same steps), then the end: what
    :func:`motiontool.cli.jsontext.dumps` writes for the whole document, one line."""
    head = {
        "schema": "motiontool.sample",
        "schema_version": 1,
        "stamps": stamps(),
        "file": path,
        "timestep_ms": timestep_ms,
        "joints": list(joints),
        "units": {
            "elapsed_ms": "ms",
            "targets": "rad (m for linear joints); null = no command; 'nan', 'inf', '-inf' ="
            " a non-finite command Webots sends to the motor",
        },
    }
    clean, escaped = escape_undecodable(head)
    yield json.dumps(clean, ensure_ascii=False)[:-1] + ', "elapsed_ms": ['
    for k, times in enumerate(elapsed):
        yield (", " if k else "") + str(times.tolist())[1:-1]
    yield '], "targets": ['
    for k, chunk in enumerate(stream):
        yield (", " if k else "") + _json_targets(chunk)
    yield "]" + (f', "{ESCAPED_BYTES}": {escaped}' if escaped else "") + "}\n"
