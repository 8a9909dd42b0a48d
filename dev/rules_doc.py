"""Write docs/rules.md from the rule records (``motiontool.cli.rule.rules_markdown``), the page
SARIF's ``helpUri`` points to; ``tests/cli/test_rule.py`` fails while it is stale.

Run from the repository root: ``.venv/bin/python dev/rules_doc.py``.
"""

from __future__ import annotations

from pathlib import Path

from motiontool.cli.rule import rules_markdown

if __name__ == "__main__":
    out = Path(__file__).resolve().parent.parent / "docs" / "rules.md"
    out.write_text(rules_markdown(), encoding="utf-8")
    print(f"wrote {out}")
