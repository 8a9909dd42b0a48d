"""The Webots world of a run, in its Rerun recording: the play report's ``world`` object
(:meth:`motiontool.sim.world_run.WorldRun.report`) where a viewer's user reads it.

- ``/webots_world``: a Markdown ``TextDocument`` (the world file and its sha256, the robot node,
  a table of the fields applied with their values, units and how, a table of those not applied
  with why, the nodes skipped), shown in its own tab beside the event log; and the same facts
  as static ``AnyValues`` columns (``path``, ``sha256``, ``robot_node``, ``applied``,
  ``applied_value``, ``applied_as``, ``not_applied``, ``not_applied_value``, ``reason``,
  ``skipped_nodes``): what a script reading the recording back finds;
- the recording property ``world``: the file, its sha256 and the robot node.

Imports :mod:`rerun` lazily, as :mod:`motiontool.sim.recording` does (which calls it).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import rerun

__all__ = ["WORLD_ENTITY", "log_world", "world_markdown"]

WORLD_ENTITY = "/webots_world"
"""Where the world's facts are logged (``/world`` is the 3D scene)."""


def _value(value: Any, unit: str | None) -> str:
    """A field's value as the world file writes it (``TRUE``, ``0 0 1 3.14159``), its unit after."""
    if isinstance(value, bool):
        text = "TRUE" if value else "FALSE"
    elif isinstance(value, list | tuple):
        text = " ".join(_value(v, None) for v in value)
    elif isinstance(value, float):
        text = f"{value:g}"
    else:
        text = str(value)
    return f"{text} {unit}" if unit else text


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _node(doc: Mapping[str, Any]) -> str:
    node = doc["robot_node"]
    return f"{node['type']} '{node['name']}'" + (f" (DEF {node['def']})" if node["def"] else "")


def world_markdown(doc: Mapping[str, Any]) -> str:
    """The play report's ``world`` object ``doc`` as a Markdown document."""
    lines = [
        "# Webots world",
        "",
        f"- file: `{doc['path']}` (Webots {doc['version']})",
        f"- sha256: `{doc['sha256']}`",
        f"- robot node that played: {_node(doc)}",
        "",
        "## Applied",
        "",
        "| field | value | applied as |",
        "|---|---|---|",
    ]
    for e in doc["applied"]:
        value = _value(e["value"], e["unit"])
        lines.append(f"| {_cell(e['field'])} | {_cell(value)} | {_cell(e['applied_as'])} |")
    lines += ["", "## Not applied", "", "| field | value | why |", "|---|---|---|"]
    for e in doc["not_applied"]:
        value = _value(e["value"], e["unit"])
        lines.append(f"| {_cell(e['field'])} | {_cell(value)} | {_cell(e['reason'])} |")
    if doc["skipped_nodes"]:
        lines += ["", "## Nodes not simulated", ""]
        lines += [f"- {line}" for line in doc["skipped_nodes"]]
    return "\n".join(lines) + "\n"


def _columns(doc: Mapping[str, Any]) -> dict[str, Sequence[str]]:
    """The world's facts as columns of text, the empty ones left out (no type to give them)."""
    applied, not_applied = doc["applied"], doc["not_applied"]
    columns = {
        "applied": [e["field"] for e in applied],
        "applied_value": [_value(e["value"], e["unit"]) for e in applied],
        "applied_as": [e["applied_as"] for e in applied],
        "not_applied": [e["field"] for e in not_applied],
        "not_applied_value": [_value(e["value"], e["unit"]) for e in not_applied],
        "reason": [e["reason"] for e in not_applied],
        "skipped_nodes": list(doc["skipped_nodes"]),
    }
    return {name: values for name, values in columns.items() if values}


def log_world(rec: rerun.RecordingStream, doc: Mapping[str, Any]) -> None:
    """Log the play report's ``world`` object ``doc`` (static: the world holds for the run)."""
    import rerun as rr

    facts = {"path": str(doc["path"]), "sha256": str(doc["sha256"]), "robot_node": _node(doc)}
    rec.log(
        WORLD_ENTITY,
        rr.TextDocument(world_markdown(doc), media_type=rr.MediaType.MARKDOWN),
        static=True,
    )
    columns = rr.AnyValues(drop_untyped_nones=True, **facts, **_columns(doc))
    rec.log(WORLD_ENTITY, columns, static=True)
    rec.send_property("world", rr.AnyValues(drop_untyped_nones=True, **facts))
