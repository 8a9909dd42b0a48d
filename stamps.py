"""Version stamps for every report: the tool and the libraries that produced the numbers.

At the top of the package so that every layer (motionfmt, kinematics, sim, cli) may stamp its
reports: versions come from package metadata, so no library is imported to read them.
"""

from __future__ import annotations

__all__ = ["stamps"]

_LIBRARIES = {"mujoco": "mujoco", "pinocchio": "pin", "rerun": "rerun-sdk", "numpy": "numpy"}


def _version(dist: str) -> str | None:
    from importlib import metadata  # imported when a report is stamped, not at start-up

    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def stamps(model_hash: str | None = None) -> dict[str, str | None]:
    """Tool and library versions (read from package metadata, without importing them)."""
    from motiontool import __version__

    out: dict[str, str | None] = {"motiontool": __version__}
    out.update({name: _version(dist) for name, dist in _LIBRARIES.items()})
    out["model_sha256"] = model_hash
    return out
