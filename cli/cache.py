"""``motiontool cache``: what batch's result cache holds, and emptying it."""

from __future__ import annotations

import enum
from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli.options import finite

__all__ = ["cache_command"]


class Action(enum.StrEnum):
    info = "info"
    clean = "clean"


def _mb(size_bytes: int) -> str:
    from motiontool.sim.cache import BYTES_PER_MB

    return f"{size_bytes / BYTES_PER_MB:.1f} MB"


def cache_command(
    action: Annotated[
        Action, typer.Argument(help="info: what the cache holds; clean: remove results.")
    ],
    cache_dir: Annotated[
        Path | None,
        typer.Option("--cache-dir", help="The cache (default ~/.cache/motiontool/batch)."),
    ] = None,
    max_mb: Annotated[
        float,
        typer.Option(
            "--max-mb",
            min=0,
            callback=finite,
            help="clean: keep the most recently used results up to this many MB (default 0: "
            "remove every result).",
        ),
    ] = 0.0,
) -> None:
    """batch's result cache: 'info' prints its folder, results and size; 'clean' removes
    results (all of them, or the least recently used down to --max-mb) and says what it did."""
    from motiontool.sim.cache import BYTES_PER_MB, DEFAULT_MAX_MB, ResultCache, default_cache_dir

    cache = ResultCache(cache_dir or default_cache_dir())
    if action is Action.info:
        usage = cache.usage()
        typer.echo(
            f"{cache.directory}: {usage.results} results, {_mb(usage.size_bytes)} "
            f"(batch prunes it to {DEFAULT_MAX_MB} MB unless --cache-max-mb says otherwise)"
        )
        return
    removed = cache.prune(round(max_mb * BYTES_PER_MB))
    left = cache.usage()
    typer.echo(
        f"removed {removed.results} results ({_mb(removed.size_bytes)}) from {cache.directory}; "
        f"{left.results} left ({_mb(left.size_bytes)})"
    )
