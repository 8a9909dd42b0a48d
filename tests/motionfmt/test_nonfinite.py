"""One check refuses a ``nan`` / ``inf`` command (MT113) for every writer and edit: the same
error type, at the same cell, with each caller's words."""

from __future__ import annotations

import pickle
from collections.abc import Callable

import numpy as np
import pytest

from motiontool.motionfmt import (
    Motion,
    MotionDocument,
    MotionSyntaxError,
    MotionToolError,
    format_motion,
    loads,
)
from motiontool.motionfmt.nonfinite import NonFiniteCommandError, refuse_non_finite
from motiontool.motionfmt.ops.concat import concat
from motiontool.motionfmt.ops.mirror import mirror
from motiontool.motionfmt.ops.scale import scale
from motiontool.motionfmt.ops.trim import trim
from motiontool.motionfmt.resample import resample

#: The first bad cell, pose by pose, then column by column: B = -inf on line 3 (line 2 has no
#: command for B, and A = nan comes after B).
BAD = b"#WEBOTS_MOTION,V1.0,B,A\n0,P1,*,0\n100,P2,-inf, nan\n"
OK = b"#WEBOTS_MOTION,V1.0,B,A\n0,P1,0,0\n100,P2,1,1\n"

EDITS: dict[str, Callable[[MotionDocument], object]] = {
    "mirroring": lambda doc: mirror(doc, {"A": ("B", 1), "B": ("A", 1)}),
    "concatenating": lambda doc: concat([doc, loads(OK, "ok.motion")], transition_ms=10),
    "trimming": lambda doc: trim(doc, 10, 50),
    "scaling": lambda doc: scale(doc, 2.0),
    "resampling": lambda doc: resample(doc, step_ms=20),
}


@pytest.mark.parametrize("before", sorted(EDITS))
def test_every_edit_refuses_the_first_non_finite_command_at_its_cell(before: str) -> None:
    doc = loads(BAD, "bad.motion")
    with pytest.raises(NonFiniteCommandError) as info:
        EDITS[before](doc)
    err = info.value
    assert isinstance(err, MotionSyntaxError) and isinstance(err, MotionToolError)
    assert str(err) == (
        "bad.motion:3:8: B = -inf is not a finite number (MT113): write a number, or '*' for"
        f" no command, before {before}"
    )
    assert (err.path, err.line, err.column, err.located) == ("bad.motion", 3, 8, True)
    assert (err.joint, err.value, err.time_ms) == ("B", -np.inf, 100)


def test_writing_a_motion_built_in_memory_names_the_pose_time() -> None:
    values = np.array([[0.0, 0.0], [np.nan, 1.0]])
    commanded = np.array([[True, True], [True, True]])
    motion = Motion(("A", "B"), ("P1", "P2"), np.array([0, 40]), values, commanded)
    with pytest.raises(NonFiniteCommandError) as info:
        format_motion(motion)
    err = info.value
    assert str(err) == "cannot write A = nan at 40 ms: a joint command must be a finite number"
    assert not err.located and (err.joint, err.time_ms) == ("A", 40)
    again = pickle.loads(pickle.dumps(err))  # crosses a process pool as the same line
    assert isinstance(again, NonFiniteCommandError) and str(again) == str(err)


def test_commands_that_are_finite_or_not_commanded_pass() -> None:
    doc = loads(b"#WEBOTS_MOTION,V1.0,A\n0,P1,*\n100,P2,-9999999.9\n200,P3,1e308\n")
    refuse_non_finite(doc.motion, doc.result, "checking")
    refuse_non_finite(doc.motion)
