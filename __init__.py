"""motiontool: lint, transform and simulate Webots ``.motion`` files."""

from __future__ import annotations

import functools

__all__ = ["__version__"]


@functools.cache
def _version() -> str:
    """The version in ``pyproject.toml``, its one home: read from the file beside this one in a
    checkout or an sdist (so an editable install never reports a stale number), else from the
    installed distribution's metadata, which the build wrote from it."""
    import tomllib  # read when asked (PEP 562, below), not at every start-up
    from pathlib import Path

    pyproject = Path(__file__).with_name("pyproject.toml")
    try:
        project = tomllib.loads(pyproject.read_text(encoding="utf-8")).get("project", {})
    except (OSError, ValueError):
        project = {}
    if project.get("name") == "motiontool" and isinstance(project.get("version"), str):
        return str(project["version"])
    from importlib import metadata  # 20 ms of start-up that a checkout never needs

    try:
        return metadata.version("motiontool")
    except metadata.PackageNotFoundError:
        return "0+unknown"


def __getattr__(name: str) -> str:
    if name == "__version__":
        return _version()
    raise AttributeError(f"module 'motiontool' has no attribute {name!r}")
