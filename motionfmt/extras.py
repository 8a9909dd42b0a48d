"""The import path of motiontool 0.1 for the extras helper, which lives in
:mod:`motiontool.extras` (every layer needs it; motiontool's own modules import it from there)."""

from motiontool.extras import EXTRAS, install_hint, require, require_installed

__all__ = ["EXTRAS", "install_hint", "require", "require_installed"]
