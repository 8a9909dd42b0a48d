"""Optional dependencies: which extra of the ``motiontool`` package brings which library.

``pip install motiontool`` installs the light core (numpy, typer): reading, validating against
the built-in robots' limits and velocities, transforming and writing motion files. Everything
heavy is an extra, imported lazily through :func:`require` at the one adapter module that uses
it, so a missing one is a one-line error naming the ``pip install`` to run
(:class:`~motiontool.errors.MissingExtraError`), never a traceback.
"""

from __future__ import annotations

import importlib
import importlib.util
from types import ModuleType

from motiontool.errors import MissingExtraError

__all__ = ["EXTRAS", "install_hint", "require", "require_installed"]

#: extra -> (the top-level modules it brings, what it gives, for people).
EXTRAS: dict[str, tuple[tuple[str, ...], str]] = {
    "kinematics": (("pinocchio", "coal"), "Pinocchio: self-collision, balance, IK, URDF robots"),
    "sim": (("mujoco", "junitparser"), "MuJoCo: play, batch (with its JUnit report)"),
    "rerun": (("rerun",), "Rerun recordings of play and batch"),
    "plot": (("matplotlib",), "matplotlib: plot, and the plots of diff"),
    "erd": (("example_robot_data",), "example-robot-data robots (erd:<name>)"),
    "ray": (("ray",), "the Ray executor of batch"),
    "lsp": (("pygls", "lsprotocol"), "pygls: motiontool server, findings in the editor"),
    "watch": (("watchfiles",), "watchfiles: motiontool watch, re-checked and re-played on save"),
    "ros": (
        ("rosbags", "mcap", "mcap_ros2", "ruamel"),
        "rosbags, mcap: ROS 2 bags and trajectories (convert, and a bag of a play run)",
    ),
}

#: How people call the library a module belongs to.
_LIBRARIES = {
    "pinocchio": "Pinocchio",
    "coal": "coal (Pinocchio's collision library)",
    "mujoco": "MuJoCo",
    "junitparser": "junitparser",
    "rerun": "Rerun (rerun-sdk)",
    "matplotlib": "matplotlib",
    "example_robot_data": "example-robot-data",
    "ray": "Ray",
    "pygls": "pygls",
    "watchfiles": "watchfiles",
    "lsprotocol": "lsprotocol (pygls' LSP types)",
    "rosbags": "rosbags",
    "mcap": "mcap",
    "mcap_ros2": "mcap-ros2-support",
    "ruamel": "ruamel.yaml",
}


def install_hint(extra: str) -> str:
    """``pip install 'motiontool[sim]'``: the command that installs ``extra``."""
    return f"pip install 'motiontool[{extra}]'"


def require(module: str, extra: str, what: str) -> ModuleType:
    """Import ``module`` (``mujoco``, ``rerun.blueprint``, ...) or say which extra brings it.

    Args:
        module: dotted module name.
        extra: the extra of ``motiontool`` that installs it (a key of :data:`EXTRAS`).
        what: the command or feature that needs it, for the message (``motiontool play``).

    Raises:
        MissingExtraError: the module (or a library it needs) cannot be imported; the message
            is one line: ``motiontool play needs MuJoCo: pip install 'motiontool[sim]'``.
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        if _interrupted(exc):  # Ctrl-C in a compiled module's import: not a missing extra
            raise KeyboardInterrupt from exc
        top = module.partition(".")[0]
        raise MissingExtraError(top, extra, what, _LIBRARIES.get(top, top)) from exc


def _interrupted(exc: BaseException) -> bool:
    """Whether a Ctrl-C is behind ``exc``: a compiled (pybind11) module whose initialisation
    is interrupted fails to import with ``ImportError: initialization failed``, caused by the
    ``KeyboardInterrupt``."""
    seen: set[int] = set()
    cause: BaseException | None = exc
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, KeyboardInterrupt):
            return True
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return False


def require_installed(module: str, extra: str, what: str) -> None:
    """Check that ``module`` is installed, without importing it (importing Pinocchio costs
    0.15 s that a check may not need); :func:`require` when it is used.

    Raises:
        MissingExtraError: as :func:`require`, when no installed package provides ``module``.
    """
    try:
        found = importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):  # a parent package missing, or None in sys.modules
        found = False
    if not found:
        top = module.partition(".")[0]
        raise MissingExtraError(top, extra, what, _LIBRARIES.get(top, top))
