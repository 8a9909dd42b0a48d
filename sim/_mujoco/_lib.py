"""What is read from the installed MuJoCo itself: its version and its warnings' names."""

from __future__ import annotations

import re

from motiontool.sim._mujoco.api import mj


def warning_label(enum_name: str) -> str:
    """The report key of a MuJoCo warning, from its ``mjtWarning`` name: ``mjWARN_BADQACC``
    -> ``bad_qacc``, ``mjWARN_CONTACTFULL`` -> ``contact_full``, ``mjWARN_CNSTRFULL`` ->
    ``constraint_full`` (a name this does not know comes out lower-cased)."""
    word = enum_name.removeprefix("mjWARN_").lower().replace("cnstr", "constraint")
    word = re.sub(r"^bad(?=.)", "bad_", word)
    return re.sub(r"(?<=[a-z])full$", "_full", word)


def warning_labels() -> dict[int, str]:
    """Index in ``MjData.warning`` -> report key, for every warning of the installed MuJoCo
    (read from ``mujoco.mjtWarning``, so that a version that adds or reorders warnings is
    labelled right)."""
    mujoco = mj()

    members = mujoco.mjtWarning.__members__
    return {
        int(value): warning_label(name)
        for name, value in sorted(members.items(), key=lambda item: int(item[1]))
        if name.startswith("mjWARN_")
    }


def mujoco_version() -> str:
    """The MuJoCo version string."""
    mujoco = mj()

    return str(mujoco.__version__)
