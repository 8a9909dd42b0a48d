"""JSON Schemas (draft 2020-12) of the JSON reports, shipped with the package.

One file per report, ``<name>.schema.json`` (:data:`NAMES`). A report's ``schema`` field is
``motiontool.<name>``; its ``schema_version`` is the schema's. ``config.schema.json``
(:data:`CONFIG`) describes the configuration, ``[tool.motiontool]``; ``defs.schema.json``
(:data:`DEFS`) holds what several reports share. A schema refers to another by its ``$id``
(``batch``'s runs are ``play`` reports), so validate with :func:`registry`, which holds every
shipped schema (it needs ``jsonschema``, which brings ``referencing``)::

    import jsonschema
    from motiontool.cli import schemas

    jsonschema.validate(report, schemas.load("batch"), registry=schemas.registry())

May import the standard library (and ``jsonschema``, inside :func:`registry`); data, read by the
rest of ``cli`` and by the tests.
"""

from __future__ import annotations

import json
from importlib import resources
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from referencing import Registry

__all__ = ["CONFIG", "DEFS", "NAMES", "load", "path_of", "registry"]

NAMES = (
    "validate",
    "info",
    "sample",
    "diff",
    "play",
    "batch",
    "robot",
    "concat",
    "mirror",
    "mirror_map",
    "resample",
    "retime",
    "scale",
    "trim",
    "rule",
    "statistics",
)
"""The reports that have a schema (``motiontool.<name>``)."""


CONFIG = "config"
"""The schema of the configuration (``[tool.motiontool]``, ``motiontool.toml``), not a report."""

DEFS = "defs"
"""Definitions several reports' schemas share by ``$ref`` (stamps, findings), not a report."""


def path_of(name: str) -> str:
    """The file name of report ``name``'s schema (or :data:`CONFIG`'s, :data:`DEFS`') inside
    this package."""
    if name not in (*NAMES, CONFIG, DEFS):
        raise ValueError(f"no schema for {name!r}; schemas: {', '.join((*NAMES, CONFIG))}")
    return f"{name}.schema.json"


def load(name: str) -> dict[str, Any]:
    """The JSON Schema of report ``name`` (one of :data:`NAMES`), as a dict."""
    text = resources.files(__name__).joinpath(path_of(name)).read_text(encoding="utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema


def registry() -> Registry[Any]:
    """Every shipped schema by its ``$id`` (``urn:motiontool:schema:play:1``), for a validator
    to resolve the ``$ref`` of one schema to another: ``Draft202012Validator(schema,
    registry=registry())``. Needs ``referencing`` (installed with ``jsonschema``)."""
    from referencing import Registry
    from referencing.jsonschema import DRAFT202012

    schemas = [load(name) for name in (*NAMES, CONFIG, DEFS)]
    return Registry().with_resources(
        (schema["$id"], DRAFT202012.create_resource(schema)) for schema in schemas
    )
