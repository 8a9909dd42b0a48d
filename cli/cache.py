"""``motiontool cache``: what the result caches hold (batch's results, validate's findings,
play --bag's robot descriptions, configuration files' tables), and emptying them."""

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
    from motiontool.disk_cache import BYTES_PER_MB

    return f"{size_bytes / BYTES_PER_MB:.1f} MB"


def cache_command(
    action: Annotated[
        Action, typer.Argument(help="info: what the caches hold; clean: remove results.")
    ],
    cache_dir: Annotated[
        Path | None,
        typer.Option(
            "--cache-dir",
            help="One cache folder (batch's --cache-dir); default: batch's results "
            "(~/.cache/motiontool/batch), validate's findings (~/.cache/motiontool/lint) and "
            "play --bag's robot descriptions (~/.cache/motiontool/urdf), configuration files' "
            "tables (~/.cache/motiontool/config).",
        ),
    ] = None,
    max_mb: Annotated[
        float,
        typer.Option(
            "--max-mb",
            min=0,
            callback=finite,
            help="clean: keep the most recently used results up to this many MB in each "
            "cache (default 0: remove every result).",
        ),
    ] = 0.0,
) -> None:
    """The result caches: 'info' prints each one's folder, results and size; 'clean' removes
    results (all of them, or the least recently used down to --max-mb) and says what it did,
    a line per cache."""
    from motiontool.cli import config_cache
    from motiontool.disk_cache import BYTES_PER_MB, ResultCache
    from motiontool.kinematics.checks.findings_cache import MAX_MB, lint_cache_dir
    from motiontool.kinematics.export import URDF_KEPT, urdf_cache_dir
    from motiontool.sim.batch import DEFAULT_MAX_MB, default_cache_dir

    caches = (
        [(ResultCache(cache_dir), "")]
        if cache_dir is not None
        else [
            (
                ResultCache(default_cache_dir()),
                f"batch prunes it to {DEFAULT_MAX_MB} MB unless --cache-max-mb says otherwise",
            ),
            (ResultCache(lint_cache_dir()), f"validate's robot findings, pruned to {MAX_MB} MB"),
            (
                ResultCache(urdf_cache_dir()),
                f"play --bag's robot descriptions, the last {URDF_KEPT} robots",
            ),
            (config_cache.cache(), "configuration files' tables, read without parsing again"),
        ]
    )
    for cache, about in caches:
        if action is Action.info:
            usage = cache.usage()
            note = f" ({about})" if about else ""
            typer.echo(f"{cache.directory}: {usage.results} results, {_mb(usage.size_bytes)}{note}")
            continue
        removed = cache.prune(round(max_mb * BYTES_PER_MB))
        left = cache.usage()
        typer.echo(
            f"removed {removed.results} results ({_mb(removed.size_bytes)}) from "
            f"{cache.directory}; {left.results} left ({_mb(left.size_bytes)})"
        )
