"""The packages whose public names are imported on first use (``motiontool.lazy_names``) say
each name three times: imported under ``TYPE_CHECKING`` (for type checkers), in ``_HOMES``
(where it is imported from at run time) and in ``__all__`` (besides what the package defines
itself). These tests keep the three in agreement, and check that each name resolves to the
object of its home."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

import motiontool

ROOT = Path(motiontool.__file__).resolve().parent
LAZY_PACKAGES = sorted(
    ".".join(("motiontool", *p.parent.relative_to(ROOT).parts))
    for p in ROOT.rglob("__init__.py")
    if "lazy_names" in p.read_text(encoding="utf-8")
    and not {"build", ".venv", "tests"} & set(p.relative_to(ROOT).parts)
)


def _type_checking_imports(package: str) -> dict[str, str]:
    """Name -> module of the ``from X import name`` statements under ``if TYPE_CHECKING``."""
    path = ROOT.joinpath(*package.split(".")[1:], "__init__.py")
    names: dict[str, str] = {}
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for stmt in node.body:
                if isinstance(stmt, ast.ImportFrom) and stmt.module:
                    names.update({a.asname or a.name: stmt.module for a in stmt.names})
    return names


def test_the_lazy_packages_are_found() -> None:
    assert {"motiontool.motionfmt", "motiontool.kinematics"} <= set(LAZY_PACKAGES)


@pytest.mark.parametrize("package", LAZY_PACKAGES)
def test_lazy_names_agree_and_resolve(package: str) -> None:
    module = importlib.import_module(package)
    homes: dict[str, str] = module._HOMES
    assert _type_checking_imports(package) == homes, "TYPE_CHECKING imports and _HOMES differ"
    defined = {n for n in module.__all__ if n in vars(module) and n not in homes}
    assert set(module.__all__) == set(homes) | defined, "__all__ and _HOMES differ"
    for name, home in homes.items():
        assert getattr(module, name) is getattr(importlib.import_module(home), name), name
