"""JSON Schemas (draft 2020-12) of the JSON reports, shipped with the package.

One file per report, ``<name>.schema.json``: ``validate``, ``info``, ``sample``, ``diff``,
``play`` and ``batch``. Validate a report with any JSON Schema tool, e.g.::

    import jsonschema
    from motiontool.cli import schemas

    jsonschema.validate(report, schemas.load("validate"))

A report's ``schema`` field is ``motiontool.<name>``; its ``schema_version`` is the schema's.
``config.schema.json`` (:data:`CONFIG`) describes the configuration, ``[tool.motiontool]``.
"""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

__all__ = ["CONFIG", "NAMES", "load", "path_of"]

NAMES = ("validate", "info", "sample", "diff", "play", "batch")
"""The reports that have a schema (``motiontool.<name>``)."""


CONFIG = "config"
"""The schema of the configuration (``[tool.motiontool]``, ``motiontool.toml``), not a report."""


def path_of(name: str) -> str:
    """The file name of report ``name``'s schema (or :data:`CONFIG`'s) inside this package."""
    if name not in (*NAMES, CONFIG):
        raise ValueError(f"no schema for {name!r}; schemas: {', '.join((*NAMES, CONFIG))}")
    return f"{name}.schema.json"


def load(name: str) -> dict[str, Any]:
    """The JSON Schema of report ``name`` (one of :data:`NAMES`), as a dict."""
    text = resources.files(__name__).joinpath(path_of(name)).read_text(encoding="utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema
