"""Write docs/rules.md, and the codes and checks tables of docs/commands.md, from the code
records and the check registry (``motiontool.cli.rule.rules_markdown``, ``codes_table``,
``checks_table``): docs/rules.md is the page SARIF's
``helpUri`` points to; ``tests/cli/test_rule.py`` fails while either is stale. The check
enums of ``cli/schemas/config.schema.json`` and ``validate.schema.json`` are written from the
registry too (:func:`schema_text`; ``tests/cli/test_registries.py`` fails while one is stale).

Run from the repository root: ``.venv/bin/python dev/rules_doc.py``.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

from motiontool.cli.rule import checks_table, codes_table, rules_markdown
from motiontool.kinematics.checks import CHECKS, DEFAULT_CHECKS

SCHEMAS = Path(__file__).resolve().parent.parent / "cli" / "schemas"
CHECK_SCHEMAS = ("config", "validate")
"""The schemas whose ``checks`` / ``check`` enums are the check registry's names."""


def with_table(page: str, table: str) -> str:
    """``page`` with the table that starts as ``table`` does (its first cell) replaced by
    ``table``; a table ends at the first blank line."""
    start = page.index(table[: table.index(" |", 2) + 2])
    end = page.index("\n\n", start) + 1
    return page[:start] + table + page[end:]


def _with_checks(node: Any, name: str, key: str | None = None) -> Any:
    """``node`` with each enum under a ``checks`` or ``check`` property set to the registry's
    names (the configuration's with ``all``), and the configuration's default named."""
    if isinstance(node, list):
        return [_with_checks(v, name, key) for v in node]
    if not isinstance(node, dict):
        return node
    out: dict[str, Any] = {}
    for k, v in node.items():
        if k == "enum" and key in ("checks", "check"):
            out[k] = [*CHECKS, "all"] if name == "config" else list(CHECKS)
        elif k == "description" and key == "checks" and name == "config":
            out[k] = re.sub(r"default [a-z, ]+\.", f"default {', '.join(DEFAULT_CHECKS)}.", v)
        else:
            out[k] = _with_checks(v, name, k if k not in ("items", "properties") else key)
    return out


def schema_text(name: str) -> str:
    """``cli/schemas/<name>.schema.json`` as it is written: its check enums from the
    registry."""
    doc = json.loads((SCHEMAS / f"{name}.schema.json").read_text(encoding="utf-8"))
    return json.dumps(_with_checks(doc, name), indent=2, ensure_ascii=False) + "\n"


if __name__ == "__main__":
    docs = Path(__file__).resolve().parent.parent / "docs"
    out = docs / "rules.md"
    out.write_text(rules_markdown(), encoding="utf-8")
    print(f"wrote {out}")
    commands = docs / "commands.md"
    page = commands.read_text(encoding="utf-8")
    page = with_table(with_table(page, codes_table()), checks_table())
    commands.write_text(page, encoding="utf-8")
    print(f"wrote the codes and checks tables of {commands}")
    for name in CHECK_SCHEMAS:
        schema = SCHEMAS / f"{name}.schema.json"
        schema.write_text(schema_text(name), encoding="utf-8")
        print(f"wrote the check enums of {schema}")
