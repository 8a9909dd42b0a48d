"""Helpers of the typed-adapter tests: count the ``Any`` of a source file, and
find what a Protocol declares that a real library object lacks."""

from __future__ import annotations

import ast
from pathlib import Path

__all__ = ["any_count", "imports_of", "members", "missing"]


def imports_of(folder: Path, tops: tuple[str, ...], root: Path) -> list[str]:
    """``path:line: module`` of every import under ``folder`` of a module in packages ``tops``
    (``pinocchio``), even under ``TYPE_CHECKING``: without stubs, its types are Any to mypy."""
    wrong = []
    for path in sorted(folder.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            else:
                continue
            wrong += [
                f"{path.relative_to(root)}:{node.lineno}: {name}"
                for name in names
                if name.split(".")[0] in tops
            ]
    return wrong


def any_count(path: Path) -> int:
    """How often ``Any`` is named in the module at ``path``: imports, annotations, ``typing.Any``."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    names = [
        node
        for node in ast.walk(tree)
        if (isinstance(node, ast.Name) and node.id == "Any")
        or (isinstance(node, ast.Attribute) and node.attr == "Any")
        or (isinstance(node, ast.alias) and node.name == "Any")
    ]
    return len(names)


def members(protocol: type) -> set[str]:
    """The attributes and methods a Protocol class declares (not its dunder machinery)."""
    declared = set(getattr(protocol, "__annotations__", {}))
    declared |= {name for name in vars(protocol) if not name.startswith("_")}
    return declared


def missing(obj: object, protocol: type) -> list[str]:
    """The members of ``protocol`` that ``obj`` does not have, sorted."""
    return sorted(name for name in members(protocol) if not hasattr(obj, name))
