"""NAOqi (a real NAO): the arguments of ``ALMotion.angleInterpolationBezier`` as JSON, and a
small Python script that sends them with ``qi``.

What it reproduces: the targets each motor holds while Webots plays the motion at the control
step (:mod:`.held`): straight lines between the poses, nothing sent across a ``*`` stretch (the
motor holds its last target, then jumps). NAOqi's plain ``angleInterpolation`` smooths between
keys in a way its documentation does not give; ``angleInterpolationBezier`` takes the curve
between two keys as a cubic Bézier with the keys' handles as its inner control points
(:mod:`.naoqi_curve`). Handles placed on the straight line to the neighbouring key make each
segment exactly that line, so the keys are the corners of Webots' stream at the control step
(``*`` cells dropped per joint; a jump after a ``*`` stretch is two keys one step apart) and
the model of NAOqi's curve gives Webots' targets back to rounding: the deviation each export
reports is that model evaluated at every step against :func:`~motiontool.motionfmt.sample`.

Times: NAOqi wants every time > 0, and a real robot must first get to the first pose from
wherever it stands (Webots jumps there at 0 ms). Every NAOqi time is Webots' playback time
plus a lead-in (:data:`~.base.DEFAULT_LEAD_IN_MS`): the robot moves from its posture to the
first key in the lead-in, then plays the motion as Webots does.

Names: the real robot's hand is one joint (``LHand``, ``RHand``, 0 closed to 1 open, as the
simulated phalanges) and one motor drives both HipYawPitch joints; Webots' ``LPhalanx1..8``
become ``LHand`` (``RPhalanx1..8``: ``RHand``) and ``RHipYawPitch`` follows ``LHipYawPitch``
(the robot checks of nao-v5 require the coupled joints to agree).
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionToolError
from motiontool.motionfmt.convert.base import Deviation, Exported, ExportOptions, RobotStream
from motiontool.motionfmt.convert.held import HeldStream, corner_keys, held_stream
from motiontool.motionfmt.convert.naoqi_curve import BEZIER_HANDLE, Key, curve_at
from motiontool.motionfmt.convert.naoqi_script import script
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["NAOQI_NAMES", "write_naoqi"]

#: Webots motor -> the NAOqi joint that moves it on the real robot (others keep their name).
NAOQI_NAMES: dict[str, str] = {
    **{f"{side}Phalanx{i}": f"{side}Hand" for side in "LR" for i in range(1, 9)},
    "RHipYawPitch": "LHipYawPitch",
}


def _keys(t_s: npt.NDArray[np.float64], q: npt.NDArray[np.float64]) -> list[Key]:
    """Keys at times ``t_s`` (s) with angles ``q`` (rad), each handle a third of the way to
    its neighbour along the straight line (the first key's first handle flat, as Choregraphe
    writes it: the robot comes to rest there from its posture)."""
    keys: list[Key] = []
    n = t_s.shape[0]
    for i in range(n):
        t, a = float(t_s[i]), float(q[i])
        if i == 0:
            before = (BEZIER_HANDLE, -t / 3.0, 0.0)
        else:
            before = (BEZIER_HANDLE, (float(t_s[i - 1]) - t) / 3.0, (float(q[i - 1]) - a) / 3.0)
        if i == n - 1:
            after = (BEZIER_HANDLE, 0.0, 0.0)
        else:
            after = (BEZIER_HANDLE, (float(t_s[i + 1]) - t) / 3.0, (float(q[i + 1]) - a) / 3.0)
        keys.append((a, before, after))
    return keys


def _joints(held: HeldStream) -> dict[str, int]:
    """NAOqi name -> the column of ``held`` that drives it (the first of the motion's motors
    that maps to it and is ever commanded)."""
    import numpy as np

    chosen: dict[str, int] = {}
    for k, motor in enumerate(held.motors):
        name = NAOQI_NAMES.get(motor, motor)
        if name not in chosen and bool(np.any(~np.isnan(held.targets[:, k]))):
            chosen[name] = k
    return chosen


def _deviation(held: HeldStream, columns: dict[str, int], model: dict[str, Any]) -> Deviation:
    """Worst |NAOqi model - Webots' held target| over every step where a motor holds one."""
    import numpy as np

    worst, joint, at = 0.0, None, None
    compared = 0
    for k, motor in enumerate(held.motors):
        name = NAOQI_NAMES.get(motor, motor)
        if name not in columns:
            continue
        got = model[name]
        want = held.targets[:, k]
        mask = ~np.isnan(want) & ~np.isnan(got)
        compared += int(mask.sum())
        err = np.where(mask, np.abs(got - want), 0.0)
        i = int(np.argmax(err))
        if err[i] > worst or joint is None:
            worst, joint, at = float(err[i]), motor, int(held.elapsed_ms[i])
    what = f"{compared} targets, every control step of every motor from its first command on"
    return Deviation(worst, joint, at, what)


def write_naoqi(motion: Motion, options: ExportOptions) -> Exported:
    """The JSON of ``angleInterpolationBezier``'s arguments, with its script as a companion."""
    import numpy as np

    if options.lead_in_ms <= 0:
        raise MotionToolError(
            f"the lead-in must be > 0 ms (NAOqi times are), got {options.lead_in_ms}"
        )
    held = held_stream(motion, options.timestep_ms)
    columns = _joints(held)
    if not columns:
        raise MotionToolError("no joint of the motion is ever commanded: nothing to send")
    t_s = (held.elapsed_ms.astype(np.float64) + options.lead_in_ms) / MS_PER_S
    names, times, keys = [], [], []
    model: dict[str, Any] = {}
    for name, k in columns.items():
        live = np.nonzero(~np.isnan(held.targets[:, k]))[0]
        picked = live[corner_keys(held.targets[live, k])]
        names.append(name)
        times.append([float(x) for x in t_s[picked]])
        keys.append(_keys(t_s[picked], held.targets[picked, k]))
        model[name] = curve_at(times[-1], keys[-1], t_s)
    deviation = _deviation(held, columns, model)
    doc = _document(options, names, times, keys, deviation)
    data = (json.dumps(doc, indent=1) + "\n").encode("utf-8", "surrogateescape")
    n_keys = sum(len(t) for t in times)
    stream = RobotStream(
        tuple(held.motors[k] for k in columns.values()),
        held.elapsed_ms,
        np.column_stack([model[name] for name in names]),
    )
    detail = (
        f"{n_keys} keys of {len(names)} NAOqi joints for angleInterpolationBezier, "
        f"times + {options.lead_in_ms} ms lead-in"
    )
    companion = ("_send.py", script(options.target_name or "motion.naoqi.json").encode())
    return Exported(data, n_keys, detail, deviation, (companion,), stream)


def _document(
    options: ExportOptions,
    names: list[str],
    times: list[list[float]],
    keys: list[list[Key]],
    deviation: Deviation,
) -> dict[str, Any]:
    return {
        "format": "motiontool.naoqi",
        "format_version": 1,
        "source": options.source,
        "robot": options.robot,
        "call": "ALMotion.angleInterpolationBezier",
        "units": {"times": "s", "angles": "rad (LHand, RHand: 0 closed to 1 open)"},
        "timestep_ms": options.timestep_ms,
        "lead_in_ms": options.lead_in_ms,
        "worst_deviation_rad": deviation.max_rad,
        "names": names,
        "times": times,
        "keys": [[[a, list(h1), list(h2)] for a, h1, h2 in joint] for joint in keys],
    }
