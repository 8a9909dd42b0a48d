"""Reading a Rerun recording back in tests with Rerun's own reader."""

from __future__ import annotations

from pathlib import Path
from typing import Any

__all__ = ["rrd_contents", "rrd_rows"]


def rrd_contents(path: Path) -> dict[str, list[Any]]:
    """Entity path -> the record batches of its chunks, read with Rerun's own reader."""
    from rerun.chunk import RrdReader

    reader = RrdReader(path)
    assert reader.recordings(), "no recording store"
    out: dict[str, list[Any]] = {}
    for chunk in reader.stream().collect().stream().to_chunks():
        out.setdefault(chunk.entity_path, []).append(chunk.to_record_batch())
    return out


def rrd_rows(path: Path, *, skip: tuple[str, ...] = ()) -> dict[tuple[str, str], list[str]]:
    """(entity, column) -> every row logged there, as text, sorted: what a recording holds,
    however it was cut into chunks (row ids aside; entities starting with one of ``skip``
    left out)."""
    import pyarrow as pa

    out: dict[tuple[str, str], list[str]] = {}
    for entity, batches in rrd_contents(path).items():
        if entity.startswith(skip):
            continue
        for batch in batches:
            for name in batch.schema.names:
                if "RowId" in name:
                    continue
                column = batch.column(name)
                if pa.types.is_duration(column.type) or pa.types.is_timestamp(column.type):
                    column = column.cast(pa.int64())
                out.setdefault((entity, name), []).extend(map(repr, column.to_pylist()))
    return {key: sorted(rows) for key, rows in out.items()}
