"""JSON Schemas (draft 2020-12) of the JSON reports, shipped with the package.

One file per report, ``<name>.schema.json``: ``validate``, ``info``, ``sample``, ``diff``,
``play`` and ``batch``. Validate a report with any JSON Schema tool, e.g.::

    import jsonschema
    from motiontool.cli import schemas

    jsonschema.validate(report, schemas.load("validate"))

A report's ``schema`` field is ``motiontool.<name>``; its ``schema_version`` is the schema's.
"""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

__all__ = ["NAMES", "load", "path_of"]

NAMES = ("validate", "info", "sample", "diff", "play", "batch")
"""The reports that have a schema (``motiontool.<name>``)."""


def path_of(name: str) -> str:
    """The file name of report ``name``'s schema inside this package."""
    if name not in NAMES:
        raise ValueError(f"no schema for {name!r}; schemas: {', '.join(NAMES)}")
    return f"{name}.schema.json"


def load(name: str) -> dict[str, Any]:
    """The JSON Schema of report ``name`` (one of :data:`NAMES`), as a dict."""
    text = resources.files(__name__).joinpath(path_of(name)).read_text(encoding="utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema
