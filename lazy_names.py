"""A package's public names, each imported from its module when first used (PEP 562).

A package ``__init__`` that re-exports its public names would import every module behind them
at once; ``motiontool validate`` needs a few (the reader, the check registry) and starts faster
without the rest (the document, the player, the checks, the robot specs). Such a package lists
where each name lives and hands the list to :func:`lazy_names`; ``from motiontool.motionfmt
import loads`` then works as before, importing ``motionfmt.document`` at that moment. The names
are imported under ``typing.TYPE_CHECKING`` as well, for type checkers and readers.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping

__all__ = ["lazy_names"]


def lazy_names(
    package: str, homes: Mapping[str, str]
) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """The module ``__getattr__`` and ``__dir__`` of ``package`` (its ``__name__``) whose
    names ``homes`` maps to the module each is imported from: a name is imported on first use
    and kept as the package's attribute."""
    module = sys.modules[package]

    def __getattr__(name: str) -> object:
        home = homes.get(name)
        if home is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(home), name)
        setattr(module, name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(module)) | set(homes))

    return __getattr__, __dir__
