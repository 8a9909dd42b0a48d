"""Write docs/rules.md, and the codes and checks tables of docs/commands.md, from the code
records and the check registry (``motiontool.cli.rule.rules_markdown``, ``codes_table``,
``checks_table``): docs/rules.md is the page SARIF's
``helpUri`` points to; ``tests/cli/test_rule.py`` fails while either is stale.

Run from the repository root: ``.venv/bin/python dev/rules_doc.py``.
"""

from __future__ import annotations

from pathlib import Path

from motiontool.cli.rule import checks_table, codes_table, rules_markdown


def with_table(page: str, table: str) -> str:
    """``page`` with the table that starts as ``table`` does (its first cell) replaced by
    ``table``; a table ends at the first blank line."""
    start = page.index(table[: table.index(" |", 2) + 2])
    end = page.index("\n\n", start) + 1
    return page[:start] + table + page[end:]


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
