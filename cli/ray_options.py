"""``batch --ray-runtime-env``: the Ray runtime environment of a batch's tasks, as JSON text or
a JSON file (``ray.init(runtime_env=...)``: ``py_modules``, ``pip``, ``env_vars``...)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

__all__ = ["RayRuntimeEnvOption", "runtime_env"]


def runtime_env(value: str | dict[str, object]) -> dict[str, object]:
    """Typer ``parser`` of ``--ray-runtime-env``: a JSON object, given as text (it starts with
    ``{``) or as the path of a file that holds one. Not JSON, not an object, a file that cannot
    be read: a usage error (one line, exit 2) naming where."""
    if isinstance(value, dict):
        return value
    text, where = value, "the JSON text"
    if not value.lstrip().startswith(("{", "[")):
        where = f"'{value}'"
        try:
            text = Path(value).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            reason = exc.strerror if isinstance(exc, OSError) else "not UTF-8 text"
            raise typer.BadParameter(
                f"cannot read '{value}': {reason or exc} (give a JSON object, or a file of one)"
            ) from None
    try:
        env = json.loads(text)
    except json.JSONDecodeError as exc:
        at = f"'{value}':{exc.lineno}:{exc.colno}" if where != "the JSON text" else where
        raise typer.BadParameter(f"{at}: expected a JSON object: {exc.msg}") from None
    except RecursionError:  # json recurses once per level of nesting
        raise typer.BadParameter(f"{where}: nested too deeply to read as JSON") from None
    if not isinstance(env, dict):
        raise typer.BadParameter(
            f'{where}: expected a JSON object such as {{"pip": [...]}}, got {type(env).__name__}'
        )
    return env


RayRuntimeEnvOption = Annotated[
    dict[str, object] | None,
    typer.Option(
        "--ray-runtime-env",
        parser=runtime_env,
        metavar="JSON|FILE",
        help="Ray runtime environment of the runs (py_modules, pip, env_vars...): a JSON object"
        " or a file of one (docs/ray.md).",
        show_default=False,
    ),
]
"""``batch --ray-runtime-env``."""
